#include "evaluation/colmap_peer.h"

#include <chrono>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "common/run_program.h"
#include "exports/colmap.h"

namespace rigsim {

namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;

std::string Tail(const fs::path& log, size_t lines) {
  std::ifstream in(log);
  std::vector<std::string> all;
  std::string line;
  while (std::getline(in, line)) {
    if (!line.empty()) all.push_back(line);
  }
  std::string out;
  for (size_t i = all.size() > lines ? all.size() - lines : 0; i < all.size(); ++i) {
    if (!out.empty()) out += " | ";
    out += all[i];
  }
  return out;
}

std::string Params(const Camera& camera) {
  std::vector<double> p = camera.params();
  p[2] += 0.5;  // COLMAP's pixel centres are at .5
  p[3] += 0.5;
  std::string s;
  char buf[40];
  for (double v : p) {
    std::snprintf(buf, sizeof buf, "%.17g", v);
    if (!s.empty()) s += ',';
    s += buf;
  }
  return s;
}

// Runs one COLMAP step; returns an empty string, or why it failed.
std::string Step(const ColmapPeerOptions& options, const std::string& name, std::vector<std::string> args,
                 const fs::path& log, double* seconds) {
  const auto start = Clock::now();
  args.insert(args.begin(), {options.program, name, "--log_to_stderr", "1"});
  // COLMAP's glog lines are noise here; its errors still reach the log.
  const ProgramRun run = RunProgram(args, log, {}, {"GLOG_minloglevel=2"});
  *seconds += std::chrono::duration<double>(Clock::now() - start).count();
  if (run.exit_code == 0) return "";
  if (!run.error.empty()) return "colmap " + name + ": " + run.error;
  return "colmap " + name + " exited with " + std::to_string(run.exit_code) + ": " + Tail(log, 2);
}

}  // namespace

bool ColmapAvailable(const ColmapPeerOptions& options) { return !FindProgram(options.program).empty(); }

ColmapPeerResult RunColmapPeer(const fs::path& dataset_dir, const Rig& truth, const FramesFile& frames,
                               const fs::path& work_dir, const ColmapPeerOptions& options) {
  ColmapPeerResult result;
  const auto start = Clock::now();
  const DatasetLayout layout(dataset_dir);
  fs::create_directories(work_dir / "lists");
  fs::create_directories(work_dir / "sparse");
  const fs::path database = work_dir / "database.db";
  const std::string threads = std::to_string(options.num_threads);
  auto fail = [&](const std::string& why) {
    result.failure_reason = why;
    result.time_s = std::chrono::duration<double>(Clock::now() - start).count();
    return result;
  };
  for (const RigCamera& rc : truth.cameras) {
    const fs::path list = work_dir / "lists" / (rc.name + ".txt");
    {
      std::ofstream out(list);
      for (const Frame& f : frames.frames) {
        out << layout.ImageName(rc.name, f.name) << "\n";
        ++result.images;
      }
    }
    const std::string error = Step(options, "feature_extractor",
                                   {"--database_path", database.string(), "--image_path", (dataset_dir / "images").string(),
                                    "--image_list_path", list.string(), "--ImageReader.single_camera", "1",
                                    "--ImageReader.camera_model", std::string(CameraModelName(rc.camera.model())),
                                    "--ImageReader.camera_params", Params(rc.camera), "--SiftExtraction.use_gpu", "0",
                                    "--SiftExtraction.num_threads", threads},
                                   work_dir / "extract.log", &result.extract_time_s);
    if (!error.empty()) return fail(error);
  }
  if (const std::string error = Step(options, "exhaustive_matcher",
                                     {"--database_path", database.string(), "--SiftMatching.use_gpu", "0",
                                      "--SiftMatching.num_threads", threads},
                                     work_dir / "match.log", &result.match_time_s);
      !error.empty()) {
    return fail(error);
  }
  if (const std::string error =
          Step(options, "mapper",
               {"--database_path", database.string(), "--image_path", (dataset_dir / "images").string(), "--output_path",
                (work_dir / "sparse").string(), "--Mapper.ba_refine_focal_length", "0",
                "--Mapper.ba_refine_principal_point", "0", "--Mapper.ba_refine_extra_params", "0", "--Mapper.num_threads",
                threads},
               work_dir / "mapper.log", &result.mapper_time_s);
      !error.empty()) {
    return fail(error);  // exit 1 with "failed to create sparse model": nothing registered
  }
  double convert_time = 0.0;
  for (const auto& e : fs::directory_iterator(work_dir / "sparse")) {
    if (!e.is_directory()) continue;
    const std::string error = Step(options, "model_converter",
                                   {"--input_path", e.path().string(), "--output_path", e.path().string(),
                                    "--output_type", "TXT"},
                                   work_dir / "convert.log", &convert_time);
    if (!error.empty()) return fail(error);
  }
  try {
    const fs::path model = FindColmapTextModel(work_dir / "sparse");
    std::vector<std::pair<std::string, Rigid3d>> images;
    for (const ColmapImage& image : ReadColmapImages(model / "images.txt")) images.push_back({image.name, image.cam_from_world});
    result.registered = static_cast<int>(images.size());
    result.estimate = RigEstimateFromColmap(images, truth, frames);
  } catch (const std::runtime_error& e) {
    return fail(std::string("no COLMAP model to read: ") + e.what());
  }
  result.success = true;
  result.time_s = std::chrono::duration<double>(Clock::now() - start).count();
  return result;
}

}  // namespace rigsim
