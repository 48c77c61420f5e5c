#include "report/report_writer.h"

#include <algorithm>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "common/data_dir.h"
#include "geometry/json_io.h"
#include "labels/cityscapes.h"
#include "report/report_parts.h"

namespace rigsim {
namespace fs = std::filesystem;
using Json = nlohmann::json;

namespace report_parts {

void WriteDataScript(const fs::path& path, const std::string& key, const Json& value) {
  std::ofstream out(path, std::ios::binary);
  // "</" must not appear in a script; JSON allows "<\/" for it.
  std::string text = value.dump(-1, ' ', false, Json::error_handler_t::replace);
  for (size_t i = text.find("</"); i != std::string::npos; i = text.find("</", i + 3)) text.replace(i, 2, "<\\/");
  out << "RIGSIM.put(" << Json(key).dump() << ", " << text << ");\n";
  if (!out) throw std::runtime_error(path.string() + ": cannot write");
}

Json Pose(const Rigid3d& pose) { return json_io::PoseToJson(pose); }

}  // namespace report_parts

namespace {

using report_parts::ReportContext;

void CopyFile(const fs::path& from, const fs::path& to) {
  if (!fs::exists(from)) throw std::runtime_error(from.string() + ": missing (needed by the report)");
  fs::create_directories(to.parent_path());
  fs::copy_file(from, to, fs::copy_options::overwrite_existing);
}

// three.js r111 as Debian's libjs-three installs it: the library, the glTF loader, the orbit
// controls (classic scripts, which a page opened from disk may load) and the licence.
void CopyThreeJs(const fs::path& from, const fs::path& dir) {
  if (!fs::exists(from / "three.min.js")) {
    throw std::runtime_error(from.string() +
                             ": three.js not found (install Debian's libjs-three: bash scripts/install-deps.sh)");
  }
  CopyFile(from / "three.min.js", dir / "three" / "three.min.js");
  CopyFile(from / "examples/js/loaders/GLTFLoader.js", dir / "three" / "GLTFLoader.js");
  CopyFile(from / "examples/js/controls/OrbitControls.js", dir / "three" / "OrbitControls.js");
  const fs::path licence = "/usr/share/doc/libjs-three/copyright";
  if (fs::exists(licence)) {
    CopyFile(licence, dir / "three" / "LICENSE");
  } else {
    std::ofstream(dir / "three" / "LICENSE") << "three.js (https://threejs.org), MIT licence, copyright 2010-2019 three.js authors\n";
  }
}

// A sweep's report.md, summary.json and plots, copied under sweep/; what the page shows of them.
Json CopySweep(const fs::path& sweep, const fs::path& dir) {
  if (!fs::is_directory(sweep)) throw std::runtime_error(sweep.string() + ": not a sweep folder");
  Json out = {{"folder", fs::absolute(sweep).string()}};
  auto read = [](const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  };
  if (fs::exists(sweep / "report.md")) out["report_md"] = read(sweep / "report.md");
  if (fs::exists(sweep / "summary.json")) {
    try {
      out["summary"] = Json::parse(read(sweep / "summary.json"));
    } catch (const Json::exception& e) {
      throw std::runtime_error((sweep / "summary.json").string() + ": not JSON: " + e.what());
    }
  }
  Json plots = Json::array();
  if (fs::is_directory(sweep / "plots")) {
    std::vector<fs::path> files;
    // Each plot once: its PNG, else its SVG (an <img> shows either).
    for (const auto& entry : fs::directory_iterator(sweep / "plots")) {
      const fs::path& f = entry.path();
      if (f.extension() == ".png" || (f.extension() == ".svg" && !fs::exists(fs::path(f).replace_extension(".png")))) {
        files.push_back(f);
      }
    }
    std::sort(files.begin(), files.end());
    for (const fs::path& f : files) {
      CopyFile(f, dir / "sweep" / "plots" / f.filename());
      plots.push_back("sweep/plots/" + f.filename().string());
    }
  }
  out["plots"] = plots;
  if (!out.contains("report_md") && !out.contains("summary") && plots.empty()) {
    throw std::runtime_error(sweep.string() + ": no report.md, summary.json or plots/ (is it a sweep's --out folder?)");
  }
  return out;
}

Json CamerasJson(const Rig& rig) {
  Json cameras = Json::array();
  for (const RigCamera& rc : rig.cameras) {
    const Camera& cam = rc.camera;
    cameras.push_back({{"name", rc.name},
                       {"model", std::string(CameraModelName(cam.model()))},
                       {"width", cam.width()},
                       {"height", cam.height()},
                       {"params", cam.params()},
                       {"max_angle_rad", cam.max_valid_angle()}});
  }
  return cameras;
}

Json ClassLegend(const ReliableClasses& reliable) {
  Json legend = Json::array();
  for (const LabelClass& c : CityscapesClasses()) {
    legend.push_back({{"id", c.id},
                      {"name", std::string(c.name)},
                      {"color", {c.color[0], c.color[1], c.color[2]}},
                      {"reliable", reliable.IsReliable(c.id)}});
  }
  return legend;
}

}  // namespace

void ReportOptions::Check() const {
  auto fail = [](const std::string& what) { throw std::invalid_argument("ReportOptions: " + what); };
  if (max_image_width < 16) fail("max_image_width must be >= 16");
  if (depth_grid_width < 16) fail("depth_grid_width must be >= 16");
  if (overlap_grid_width < 4) fail("overlap_grid_width must be >= 4");
  if (max_points < 0) fail("max_points must be >= 0");
}

std::vector<fs::path> ReportPageFiles(const ReportOptions& options) {
  std::vector<fs::path> files;
  for (const char* file : {"index.html", "geometry.js", "report.js", "report.css"}) {
    files.push_back(options.web_dir.empty() ? DataPath(fs::path("report/web") / file) : options.web_dir / file);
    if (!fs::exists(files.back())) throw std::runtime_error(files.back().string() + ": missing (needed by the report)");
  }
  return files;
}

std::vector<std::string> WriteReport(const CalibrationRun& run, const ReportOptions& options, const fs::path& dir) {
  options.Check();
  if (run.results.empty()) throw std::invalid_argument("WriteReport: the run has no result");
  for (const RigCalibrationResult& r : run.results) {
    if (!r.details) throw std::invalid_argument("WriteReport: the run was calibrated without keep_details");
  }
  ReportContext ctx{run, options, dir, {}, {}};
  const bool truth = run.inputs.truth && !run.inputs.frames.frames.empty() &&
                     std::all_of(run.inputs.frames.frames.begin(), run.inputs.frames.frames.end(),
                                 [](const Frame& f) { return f.rig_from_world.has_value(); });
  if (truth) {
    for (const RigCalibrationResult& r : run.results) ctx.aligned.push_back(AlignToTruth(r, *run.inputs.truth, run.inputs.frames));
  }

  for (const fs::path& file : ReportPageFiles(options)) CopyFile(file, dir / file.filename());
  CopyThreeJs(options.three_js_dir, dir);
  fs::create_directories(dir / "data");

  Json report;
  report["format"] = "rigsim-report 1";
  report["dataset"] = fs::absolute(run.inputs.dataset_dir).lexically_normal().string();
  report["command"] = options.command;
  report["tool_version"] = options.tool_version;
  report["has_truth"] = truth;
  report["cameras"] = CamerasJson(run.inputs.rig);
  Json frames = Json::array();
  for (const Frame& f : run.inputs.frames.frames) frames.push_back(f.name);
  report["frames"] = frames;
  Json modes = Json::array();
  for (const RigCalibrationResult& r : run.results) modes.push_back(r.semantic_mode);
  report["modes"] = modes;
  report["labels"] = run.labels_used ? run.options.labels.Describe() : "not used";
  report["class_legend"] = ClassLegend(run.options.reliable);
  report["views"] = report_parts::WriteViews(ctx);
  Json selftest = nullptr;
  report["pairs"] = report_parts::WritePairs(ctx, &selftest);
  report["selftest"] = selftest;
  report["scene"] = report_parts::SceneData(ctx);
  report["pipeline"] = report_parts::PipelineData(ctx);
  report["sweep"] = options.sweep_dir.empty() ? Json(nullptr) : CopySweep(options.sweep_dir, dir);
  report["warnings"] = ctx.warnings;
  report_parts::WriteDataScript(dir / "data" / "report.js", "report", report);
  return ctx.warnings;
}

}  // namespace rigsim
