// `rigsim render` options through the built binary. --photometric and its magnitudes: on, the RGB
// images change and photometric.json records the draws while labels and depth stay the same; off,
// nothing changes; bad values are refused before anything is written. --rules: a glTF without
// extras.class is labelled by name; a bad rules file is refused, naming it, before rendering. The
// ground-truth overlap is printed per camera pair, and not at all for one camera. --sensor: a named
// sensor preset.

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "dataset/dataset.h"
#include "dataset/label_image.h"
#include "labels/cityscapes.h"
#include "testing/gltf_builder.h"
#include "testing/temp_dir.h"
#include "tests/rigsim_cli.h"

namespace rigsim {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

// Each run's output beside the test's scratch files.
CliResult RunRigsim(const fs::path& dir, const std::vector<std::string>& args) { return rigsim::RunRigsim(args, dir / "rigsim"); }

class RenderCli : public testing::Test {
 protected:
  void SetUp() override {
    // A large wall 6 m down -Z (every ring camera at heading 0 sees part of it, the others sky).
    scene_ = WriteWall("wall", {{"mesh", 0}, {"extras", {{"class", "building"}}}});
    const CliResult rig = RunRigsim(dir_, {"make-rig", "--cameras", "3", "--width", "64", "--height", "48", "--out", (dir_ / "rig").string()});
    ASSERT_EQ(rig.code, 0) << rig.err;
  }

  // The wall as `name`.gltf in the test's folder; `node` places mesh 0.
  fs::path WriteWall(const std::string& name, const json& node) const {
    GltfBuilder g;
    g.Mesh({{"POSITION", g.Positions({-30, -10, -6, 30, -10, -6, 30, 20, -6, -30, -10, -6, 30, 20, -6, -30, 20, -6})}});
    g.Node(node);
    g.Scene({0});
    return g.WriteEmbedded(dir_, name);
  }

  CliResult Render(const std::string& out, std::vector<std::string> extra) {
    return RenderScene(scene_, out, std::move(extra));
  }
  CliResult RenderScene(const fs::path& scene, const std::string& out, std::vector<std::string> extra) {
    std::vector<std::string> args = {"render", "--scene", scene.string(), "--rig", (dir_ / "rig/rig.json").string(),
                                     "--frames", (dir_ / "rig/frames.json").string(), "--out", (dir_ / out).string(),
                                     "--spp", "1", "--seed", "3"};
    args.insert(args.end(), extra.begin(), extra.end());
    return RunRigsim(dir_, args);
  }

  const TempDir dir_;
  fs::path scene_;
};

TEST_F(RenderCli, PhotometricOnChangesOnlyRgbAndRecordsTheDraws) {
  const CliResult off = Render("off", {});
  ASSERT_EQ(off.code, 0) << off.err;
  EXPECT_EQ(off.out.find("photometric differences"), std::string::npos) << off.out;
  const CliResult on = Render("on", {"--photometric", "--read-noise", "0.01", "--threads", "1"});
  ASSERT_EQ(on.code, 0) << on.err;
  EXPECT_NE(on.out.find("photometric differences (seed 3"), std::string::npos) << on.out;
  const CliResult again = Render("again", {"--photometric", "--read-noise", "0.01", "--threads", "2"});
  ASSERT_EQ(again.code, 0) << again.err;

  const DatasetLayout a(dir_ / "off"), b(dir_ / "on"), c(dir_ / "again");
  EXPECT_FALSE(fs::exists(a.PhotometricJson()));
  ASSERT_TRUE(fs::exists(b.PhotometricJson()));
  for (const std::string cam : {"cam0", "cam1", "cam2"}) {
    EXPECT_NE(ReadFile(a.Image(cam, "000000")), ReadFile(b.Image(cam, "000000"))) << cam;
    EXPECT_EQ(ReadFile(b.Image(cam, "000000")), ReadFile(c.Image(cam, "000000"))) << cam << ": same seed, same bytes";
    EXPECT_EQ(ReadFile(a.Label(cam, "000000")), ReadFile(b.Label(cam, "000000"))) << cam;
    EXPECT_EQ(ReadFile(a.Instance(cam, "000000")), ReadFile(b.Instance(cam, "000000"))) << cam;
    EXPECT_EQ(ReadFile(a.Depth(cam, "000000")), ReadFile(b.Depth(cam, "000000"))) << cam;
  }
  const json j = json::parse(ReadFile(b.PhotometricJson()));
  EXPECT_EQ(j.at("seed").get<int>(), 3);
  EXPECT_EQ(j.at("options").at("read_noise_stddev").get<double>(), 0.01);
  EXPECT_EQ(j.at("options").at("vignetting_strength").get<double>(), 0.3);  // the --photometric default
  ASSERT_EQ(j.at("cameras").size(), 3u);
  EXPECT_NE(j.at("cameras")[0].at("gain"), j.at("cameras")[1].at("gain"));

  // One magnitude alone turns on only itself.
  const CliResult vignetting_only = Render("vignetting_only", {"--vignetting", "0.5"});
  ASSERT_EQ(vignetting_only.code, 0) << vignetting_only.err;
  const json v = json::parse(ReadFile(DatasetLayout(dir_ / "vignetting_only").PhotometricJson()));
  EXPECT_EQ(v.at("options").at("vignetting_strength").get<double>(), 0.5);
  EXPECT_EQ(v.at("options").at("exposure_stops_sigma").get<double>(), 0.0);
  EXPECT_EQ(v.at("cameras")[1].at("gain").get<double>(), 1.0);
}

TEST_F(RenderCli, PrintsTheOverlapOfEveryPairAndNoHeadingForOneCamera) {
  const CliResult three = Render("three", {});
  ASSERT_EQ(three.code, 0) << three.err;
  EXPECT_NE(three.out.find("ground-truth overlap"), std::string::npos) << three.out;
  for (const std::string pair : {"cam0-cam1", "cam0-cam2", "cam1-cam2"}) {
    EXPECT_NE(three.out.find("  " + pair + " "), std::string::npos) << pair << "\n" << three.out;
  }

  // A one-camera ring: make-rig's default distorted camera (index 1) does not apply.
  const CliResult rig = RunRigsim(dir_, {"make-rig", "--cameras", "1", "--width", "64", "--height", "48", "--out",
                                         (dir_ / "rig1").string()});
  ASSERT_EQ(rig.code, 0) << rig.err;
  const CliResult one = RunRigsim(dir_, {"render", "--scene", scene_.string(), "--rig", (dir_ / "rig1/rig.json").string(),
                                         "--frames", (dir_ / "rig1/frames.json").string(), "--out", (dir_ / "one").string()});
  ASSERT_EQ(one.code, 0) << one.err;
  EXPECT_NE(one.out.find("rendered 1 view (1 camera x 1 frame, "), std::string::npos) << one.out;
  EXPECT_EQ(one.out.find("overlap"), std::string::npos) << one.out;
}

// How often `needle` occurs in `text`.
int Occurrences(const std::string& text, const std::string& needle) {
  int n = 0;
  for (size_t at = text.find(needle); at != std::string::npos; at = text.find(needle, at + 1)) ++n;
  return n;
}

// In a log the count shows at each quarter and at the end, a line each; on a terminal (a pseudo-
// terminal through script(1)) it is one line rewritten in place for every view and kept at the end.
TEST_F(RenderCli, ProgressIsALineAQuarterInALogAndOneLineRewrittenOnATerminal) {
  const CliResult rig = RunRigsim(dir_, {"make-rig", "--cameras", "3", "--frames", "8", "--width", "32", "--height",
                                         "24", "--out", (dir_ / "rig8").string()});
  ASSERT_EQ(rig.code, 0) << rig.err;
  const std::vector<std::string> args = {"render", "--scene", scene_.string(), "--rig", (dir_ / "rig8/rig.json").string(),
                                         "--frames", (dir_ / "rig8/frames.json").string(), "--spp", "1"};
  std::vector<std::string> to_log = args;
  to_log.insert(to_log.end(), {"--out", (dir_ / "log").string()});
  const CliResult log = RunRigsim(dir_, to_log);
  ASSERT_EQ(log.code, 0) << log.err;
  EXPECT_EQ(Occurrences(log.err, "rendering views "), 5) << log.err;  // 1, 6, 12, 18 and 24 of 24
  EXPECT_NE(log.err.find("rendering views 6/24\n"), std::string::npos) << log.err;
  EXPECT_NE(log.err.find("rendering views 24/24\n"), std::string::npos) << log.err;
  EXPECT_EQ(log.err.find('\r'), std::string::npos) << log.err;

  std::string command = RIGSIM_BINARY;
  for (const std::string& a : args) command += " '" + a + "'";
  command += " --out '" + (dir_ / "tty").string() + "'";
  FILE* pipe = popen(("script -qec \"" + command + "\" /dev/null").c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  std::string tty;
  char buf[4096];
  for (size_t got; (got = fread(buf, 1, sizeof buf, pipe)) > 0;) tty.append(buf, got);
  ASSERT_EQ(pclose(pipe), 0) << tty;
  EXPECT_EQ(Occurrences(tty, "\r\033[Krendering views "), 24) << tty;
  EXPECT_NE(tty.find("rendering views 24/24\r\n"), std::string::npos) << tty;  // the terminal's newline
  EXPECT_EQ(tty.find("rendering views 6/24\r\n"), std::string::npos) << tty;
  EXPECT_NE(tty.find("rendered 24 views"), std::string::npos) << tty;
}

TEST_F(RenderCli, BadPhotometricMagnitudesAreRefusedBeforeWriting) {
  for (const auto& [option, value] : std::vector<std::pair<std::string, std::string>>{
           {"--vignetting", "1.5"}, {"--exposure-sigma", "-1"}, {"--read-noise", "abc"}, {"--shot-noise", "0.5"}}) {
    const CliResult r = Render("bad", {option, value});
    EXPECT_NE(r.code, 0) << option << " " << value;
    EXPECT_NE(r.err.find(option), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir_ / "bad"));
  }
}

// --sensor PRESET: the RGB images change, the ground truth does not, sensor.json and
// photometric.json record the preset's values; the same bytes with libjpeg-turbo's SIMD turned off;
// --sensor ideal is the default's bytes; a misspelt preset and --photometric beside a preset are
// refused before anything is written.
TEST_F(RenderCli, SensorPresetChangesOnlyRgbAndIsRecorded) {
  const CliResult plain = Render("plain", {});
  ASSERT_EQ(plain.code, 0) << plain.err;
  const CliResult ideal = Render("ideal", {"--sensor", "ideal"});
  ASSERT_EQ(ideal.code, 0) << ideal.err;
  const CliResult automotive = Render("automotive", {"--sensor", "automotive"});
  ASSERT_EQ(automotive.code, 0) << automotive.err;
  EXPECT_NE(automotive.out.find("sensor automotive: "), std::string::npos) << automotive.out;
  EXPECT_NE(automotive.out.find("JPEG quality 75"), std::string::npos) << automotive.out;
  ::setenv("JSIMD_FORCENONE", "1", 1);
  const CliResult no_simd = Render("no_simd", {"--sensor", "automotive", "--threads", "1"});
  ::unsetenv("JSIMD_FORCENONE");
  ASSERT_EQ(no_simd.code, 0) << no_simd.err;
  const DatasetLayout a(dir_ / "plain"), b(dir_ / "ideal"), c(dir_ / "automotive"), d(dir_ / "no_simd");
  EXPECT_FALSE(fs::exists(b.SensorJson()));
  for (const std::string cam : {"cam0", "cam1", "cam2"}) {
    EXPECT_EQ(ReadFile(a.Image(cam, "000000")), ReadFile(b.Image(cam, "000000")));
    EXPECT_NE(ReadFile(a.Image(cam, "000000")), ReadFile(c.Image(cam, "000000")));
    EXPECT_EQ(ReadFile(c.Image(cam, "000000")), ReadFile(d.Image(cam, "000000"))) << "JPEG's SIMD paths give the same bytes";
    EXPECT_EQ(ReadFile(a.Label(cam, "000000")), ReadFile(c.Label(cam, "000000")));
    EXPECT_EQ(ReadFile(a.Depth(cam, "000000")), ReadFile(c.Depth(cam, "000000")));
  }
  const json sensor = json::parse(ReadFile(c.SensorJson()));
  EXPECT_EQ(sensor.at("preset"), "automotive");
  EXPECT_EQ(sensor.at("jpeg_quality"), 75);
  EXPECT_EQ(sensor.at("defocus").at("f_number").get<double>(), 1.6);
  EXPECT_EQ(json::parse(ReadFile(c.PhotometricJson())).at("options").at("vignetting_strength").get<double>(), 0.35);
  // An override changes one value of the preset.
  const CliResult sharper = Render("sharper", {"--sensor", "automotive", "--jpeg-quality", "95", "--vignetting", "0.1"});
  ASSERT_EQ(sharper.code, 0) << sharper.err;
  EXPECT_EQ(json::parse(ReadFile(DatasetLayout(dir_ / "sharper").SensorJson())).at("jpeg_quality"), 95);
  EXPECT_EQ(json::parse(ReadFile(DatasetLayout(dir_ / "sharper").PhotometricJson())).at("options").at("vignetting_strength").get<double>(), 0.1);

  const CliResult typo = Render("bad", {"--sensor", "automotve"});
  EXPECT_NE(typo.code, 0);
  EXPECT_NE(typo.err.find("unknown sensor preset 'automotve' (did you mean 'automotive'?); the presets are: ideal, "
                          "machine-vision, automotive, phone"),
            std::string::npos)
      << typo.err;
  const CliResult both = Render("bad", {"--sensor", "phone", "--photometric"});
  EXPECT_NE(both.code, 0);
  EXPECT_NE(both.err.find("--photometric and --sensor phone"), std::string::npos) << both.err;
  EXPECT_FALSE(fs::exists(dir_ / "bad"));
  const CliResult help = RunRigsim(dir_, {"render", "--help"});
  EXPECT_NE(help.out.find("machine-vision: "), std::string::npos) << help.out;
}

TEST_F(RenderCli, RulesLabelAGltfWithoutClasses) {
  // The same wall, named but without extras.class.
  const fs::path facade = WriteWall("facade", {{"mesh", 0}, {"name", "Facade_01"}}), rules = dir_ / "rules.json";
  WriteFile(rules, R"({"rules": [{"match": "node", "glob": "Facade*", "class": "building"}]})");
  const CliResult plain = RenderScene(facade, "plain", {});
  ASSERT_EQ(plain.code, 0) << plain.err;
  const CliResult ruled = RenderScene(facade, "ruled", {"--rules", rules.string()});
  ASSERT_EQ(ruled.code, 0) << ruled.err;
  EXPECT_NE(ruled.err.find("label rules " + rules.string() + " (1 rule)"), std::string::npos) << ruled.err;
  EXPECT_EQ(ReadFrames(DatasetLayout(dir_ / "ruled").FramesJson()).label_rules, "rules.json");
  EXPECT_EQ(ReadFrames(DatasetLayout(dir_ / "plain").FramesJson()).label_rules, "");

  // cam0 faces the wall: every pixel that is not sky is the wall, unlabeled without the rules and
  // a building with them.
  const uint8_t building = FindClassByName("building")->id;
  const ImageU8 without = ReadLabelImage(DatasetLayout(dir_ / "plain").Label("cam0", "000000"));
  const ImageU8 with = ReadLabelImage(DatasetLayout(dir_ / "ruled").Label("cam0", "000000"));
  ASSERT_TRUE(with.SameSize(without.width, without.height));
  int wall = 0;
  for (size_t i = 0; i < with.data.size(); ++i) {
    if (without.data[i] == kSkyId) {
      EXPECT_EQ(with.data[i], kSkyId);
      continue;
    }
    ++wall;
    EXPECT_EQ(without.data[i], kUnlabeledId);
    EXPECT_EQ(with.data[i], building);
  }
  EXPECT_GT(wall, int(with.data.size() / 4));

  // A rules file with an unknown class: refused with its name and the rule, nothing written.
  WriteFile(rules, R"({"rules": [{"match": "node", "glob": "Facade*", "class": "buildings"}]})");
  const CliResult bad = RenderScene(facade, "bad", {"--rules", rules.string()});
  EXPECT_NE(bad.code, 0);
  EXPECT_NE(bad.err.find(rules.string()), std::string::npos) << bad.err;
  EXPECT_NE(bad.err.find("unknown class 'buildings'"), std::string::npos) << bad.err;
  EXPECT_FALSE(fs::exists(dir_ / "bad"));
}

}  // namespace
}  // namespace rigsim
