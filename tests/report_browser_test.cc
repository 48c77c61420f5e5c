// The teaching report in a real browser: `rigsim demo` at a classroom size writes a dataset, its
// calibration and the report (and `rigsim report` the same again); headless Chromium (Debian's chromium, SwiftShader for WebGL) opens
// index.html from disk. The page's self-test (?selftest=1) recomputes, with the page's own code
// and through the pair view's click path, the epipolar curves and the true correspondence that
// the C++ wrote into the report, checks that the 3D view drew, and lists every error; a screenshot
// shows the 3D view is not blank. Skipped when chromium is not installed.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "common/run_program.h"
#include "dataset/image_io.h"
#include "testing/temp_dir.h"
#include "tests/rigsim_cli.h"

namespace rigsim {
namespace {
namespace fs = std::filesystem;
using Json = nlohmann::json;

std::string Chromium() {
  for (const char* name : {"chromium", "chromium-browser"}) {
    if (std::string path = FindProgram(name); !path.empty()) return path;
  }
  return "";
}

// Headless Chromium drawing WebGL on the CPU (SwiftShader), with a fresh profile, no network.
std::vector<std::string> ChromiumArgs(const std::string& chromium, const fs::path& profile) {
  return {FindProgram("timeout"), "120", chromium, "--headless", "--no-sandbox", "--disable-gpu",
          "--enable-unsafe-swiftshader", "--use-angle=swiftshader", "--disable-background-networking",
          "--disable-component-update", "--disable-sync", "--no-first-run", "--hide-scrollbars",
          "--user-data-dir=" + profile.string(), "--window-size=1280,900", "--virtual-time-budget=60000"};
}

std::string Unescape(std::string s) {
  for (const auto& [from, to] : {std::pair<std::string, std::string>{"&lt;", "<"}, {"&gt;", ">"}, {"&quot;", "\""}, {"&amp;", "&"}}) {
    for (size_t i = s.find(from); i != std::string::npos; i = s.find(from, i + to.size())) s.replace(i, from.size(), to);
  }
  return s;
}

// The demo's report, written once: ctest runs each TEST in its own process, so the checks share
// one test (the demo takes about 6 s).
struct DemoReport {
  fs::path dir;
  int code = -1;
  std::string out;
  fs::path Index() const { return dir / "demo" / "report" / "index.html"; }
  std::string Url(const std::string& suffix = "") const { return "file://" + Index().string() + suffix; }
};

DemoReport MakeDemoReport(const fs::path& dir) {
  DemoReport d;
  d.dir = dir;
  // Classroom size: 4 cameras at 640x360, 3 frames, 1 sample per pixel (every camera calibrated).
  const CliResult demo = RunRigsim({"demo", "--out", (d.dir / "demo").string(), "--width", "640", "--height", "360",
                                    "--frames", "3", "--spp", "1"},
                                   d.dir / "demo", std::chrono::seconds(240));
  d.code = demo.code;
  d.out = demo.out + demo.err;
  return d;
}

void DemoPrintsWhereTheReportIs(const DemoReport& d) {
  EXPECT_NE(d.out.find("teaching report: " + fs::absolute(d.Index()).lexically_normal().string()), std::string::npos)
      << d.out;
  EXPECT_TRUE(fs::exists(d.dir / "demo" / "report" / "three" / "LICENSE"));
  EXPECT_TRUE(fs::exists(d.dir / "demo" / "report" / "data" / "scene.js")) << "the street embedded for the 3D view";
}

void SelfTestAgreesWithTheCpp(const DemoReport& d, const std::string& chromium) {
  const fs::path log = d.dir / "selftest.log";
  std::vector<std::string> args = ChromiumArgs(chromium, d.dir / "profile-selftest");
  args.insert(args.end(), {"--enable-logging=stderr", "--v=0", "--dump-dom", d.Url("?selftest=1")});
  const ProgramRun run = RunProgram(args, log);
  const std::string out = ReadFile(log);
  ASSERT_EQ(run.exit_code, 0) << out.substr(0, 4000);
  const size_t begin = out.find("<pre id=\"selftest\">");
  ASSERT_NE(begin, std::string::npos) << out.substr(0, 4000);
  const size_t start = begin + std::string("<pre id=\"selftest\">").size();
  const Json st = Json::parse(Unescape(out.substr(start, out.find("</pre>", start) - start)));
  SCOPED_TRACE(st.dump(1));
  ASSERT_TRUE(st.value("done", false)) << "the self-test did not finish within the virtual time";
  EXPECT_FALSE(st.contains("exception"));
  EXPECT_TRUE(st["errors"].empty()) << "errors in the page";
  EXPECT_EQ(out.find("Uncaught"), std::string::npos) << "an uncaught error in the console";
  // Every camera's view under each base image, and each step of the pipeline.
  EXPECT_EQ(st["views_drawn"].get<int>(), 4 * 3);
  EXPECT_EQ(st["pipeline_steps"].get<int>(), 6);
  // The view graph's edge table: a row with a status per camera pair.
  EXPECT_GT(st["edge_rows_expected"].get<int>(), 0);
  EXPECT_EQ(st["edge_rows"], st["edge_rows_expected"]);
  EXPECT_EQ(st["edge_rows_with_status"], st["edge_rows_expected"]);
  // The Numbers tab's tables wrap on a narrow page.
  EXPECT_GE(st["numbers_tables"].get<int>(), 2);
  EXPECT_LE(st["numbers_overflow_px"].get<double>(), 1.0) << "a table of the Numbers tab runs off a 360 px page";
  // The 3D view drew the scene and the rig over most of its canvas.
  EXPECT_GT(st["webgl"]["width"].get<int>(), 100);
  EXPECT_GT(st["webgl"]["drawn_fraction"].get<double>(), 0.3);
  // The epipolar curves of the reference pixel (of the distorted camera): the page's camera models
  // and poses give the C++'s points to far below a pixel, under the truth and under the estimate,
  // and so does the curve the pair view draws for a click there.
  ASSERT_FALSE(st["curve_truth_max_px"].is_null());
  EXPECT_GT(st["curve_truth_points"].get<int>(), 5);
  EXPECT_LT(st["curve_truth_max_px"].get<double>(), 1e-3);
  EXPECT_LT(st["view_curve_truth_px"].get<double>(), 0.5);
  // Under the estimate only where the demo's best pair has a full pose of both cameras: its 3 frames
  // at this size leave a position at the bound of what the images fix (not placed with Embree and
  // OpenCV held to their SSE2 paths), and then the page draws no estimated curve at all.
  if (st["curve_estimate_max_px"].is_null()) {
    EXPECT_TRUE(st["view_curve_estimate_px"].is_null());
  } else {
    EXPECT_LT(st["curve_estimate_max_px"].get<double>(), 1e-3);
    EXPECT_LT(st["view_curve_estimate_px"].get<double>(), 0.5);
  }
  // The true correspondence from the page's coarser range grid lands where the C++'s full-size
  // depth puts it (the reference pixel sits on a smooth surface).
  ASSERT_FALSE(st["true_point_expected"].is_null());
  ASSERT_FALSE(st["true_point_px"].is_null());
  EXPECT_LT(st["true_point_px"].get<double>(), 1.5);
}

void SceneViewIsNotBlank(const DemoReport& d, const std::string& chromium) {
  const fs::path png = d.dir / "scene.png";
  std::vector<std::string> args = ChromiumArgs(chromium, d.dir / "profile-screenshot");
  args.insert(args.end(), {"--screenshot=" + png.string(), d.Url("#scene")});
  const ProgramRun run = RunProgram(args, d.dir / "screenshot.log");
  ASSERT_EQ(run.exit_code, 0) << ReadFile(d.dir / "screenshot.log");
  const ImageU8 shot = ReadImageU8(png, 3);
  ASSERT_EQ(shot.width, 1280);
  // The 3D viewport fills the left of the page below the header: many distinct colours there
  // (a blank canvas is one colour).
  double sum = 0, sum2 = 0;
  int n = 0;
  for (int y = 200; y < 700; y += 2) {
    for (int x = 40; x < 900; x += 2) {
      const double v = shot.at(x, y, 0) + shot.at(x, y, 1) + shot.at(x, y, 2);
      sum += v;
      sum2 += v * v;
      ++n;
    }
  }
  const double stddev = std::sqrt(std::max(0.0, sum2 / n - (sum / n) * (sum / n)));
  EXPECT_GT(stddev, 20.0) << "the 3D view looks blank: " << png;
}

// `rigsim report` on the demo's dataset with its calibration folder: the same modes and labels
// give the same rig (no warning that it differs), and a sweep's files are copied in.
void ReportCommandReproducesTheCalibrationAndTakesASweep(const DemoReport& d) {
  const fs::path sweep = d.dir / "sweep";
  fs::create_directories(sweep / "plots");
  std::ofstream(sweep / "report.md") << "# a sweep\n";
  std::ofstream(sweep / "summary.json") << "{\"studies\": []}\n";
  fs::copy_file(d.dir / "demo" / "report" / "img" / "c0_f0_labels.png", sweep / "plots" / "ring_success.png");
  const fs::path out = d.dir / "report2";
  const CliResult r = RunRigsim({"report", (d.dir / "demo").string(), "--calibration", (d.dir / "demo" / "calibration").string(),
                                 "--sweep", sweep.string(), "--out", out.string()},
                                d.dir / "report2", std::chrono::seconds(240));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err.find("differs"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("report: " + fs::absolute(out / "index.html").lexically_normal().string()), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(out / "sweep" / "plots" / "ring_success.png"));
  const std::string data = ReadFile(out / "data" / "report.js");
  EXPECT_NE(data.find("# a sweep"), std::string::npos);
  EXPECT_TRUE(StagingFolders(out).empty());
  // The same dataset and options give the same report data, whichever command wrote it (the
  // command line aside).
  std::string demo_data = ReadFile(d.dir / "demo" / "report" / "data" / "view_c1_f0.js");
  EXPECT_EQ(demo_data, ReadFile(out / "data" / "view_c1_f0.js"));
  EXPECT_EQ(ReadFile(d.dir / "demo" / "report" / "data" / "pair_c1_c2.js"), ReadFile(out / "data" / "pair_c1_c2.js"));
  // Refused without --force, before calibrating.
  const CliResult again = RunRigsim({"report", (d.dir / "demo").string(), "--out", out.string()}, d.dir / "report3");
  EXPECT_EQ(again.code, 1);
  EXPECT_NE(again.err.find("--force"), std::string::npos) << again.err;
}

TEST(TeachingReport, DemoWritesItAndItWorksInChromium) {
  const TempDir dir;
  const DemoReport d = MakeDemoReport(dir);
  ASSERT_TRUE(d.code == 0 || d.code == 3) << d.out;
  ASSERT_TRUE(fs::exists(d.Index())) << d.out;
  DemoPrintsWhereTheReportIs(d);
  ReportCommandReproducesTheCalibrationAndTakesASweep(d);
  const std::string chromium = Chromium();
  if (chromium.empty()) GTEST_SKIP() << "chromium is not installed (scripts/install-deps.sh installs it)";
  SelfTestAgreesWithTheCpp(d, chromium);
  SceneViewIsNotBlank(d, chromium);
}

}  // namespace
}  // namespace rigsim
