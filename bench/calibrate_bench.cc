// Calibration speed, end to end: a 6-camera ring (60 deg apart, 95 deg hfov, 1280x720, cam1 with
// barrel distortion) rendered once on the built-in street over 2 frames of the demo path, then
// calibrated from its images as `rigsim calibrate --semantics none` does: read the images, SIFT,
// pair screening, matching, two-view, rotation averaging, tracks, positions, bundle adjustment.
// The comparison with the truth runs after the timed part (it is not calibration).
//
// Counters: the time of each stage (detect, screen, match and pose are summed over worker threads;
// the rig stages run on one), and the worst camera's errors against the rendered truth.
// Reproduce: see BENCHMARKS.md.
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include <benchmark/benchmark.h>

#include "common/data_dir.h"
#include "geometry/json_io.h"
#include "gltf/gltf_loader.h"
#include "pipeline/calibration_run.h"
#include "renderer/render_dataset.h"
#include "rigs/rig_presets.h"
#include "rigs/trajectories.h"

namespace rigsim {
namespace {
namespace fs = std::filesystem;

constexpr int kCameras = 6;
constexpr int kFrames = 2;

// Rendered once per process into a temporary folder, removed at exit.
const fs::path& SixCameraDataset() {
  struct Dataset {
    fs::path dir;
    Dataset() : dir(fs::temp_directory_path() / ("rigsim_bench_calibrate_" + std::to_string(::getpid()))) {
      const Scene scene = LoadGltf(DataPath("assets/scenes/street.glb").string());
      RenderJob job;
      job.scene = &scene;
      job.scene_name = "street.glb";
      RingRigOptions ring;
      ring.num_cameras = kCameras;
      job.rig = MakeRingRig(ring);
      job.frames = MakeDemoTrajectory(kFrames);
      job.options.samples_per_pixel = 4;
      job.options.seed = 1;
      RenderDataset(job, dir, true);
    }
    ~Dataset() { fs::remove_all(dir); }
  };
  static const Dataset dataset;
  return dataset.dir;
}

void BM_CalibrateSixCameraRing(benchmark::State& state) {
  const fs::path& dir = SixCameraDataset();
  CalibrationRunOptions options;
  options.evaluate = false;
  CalibrationRun run;
  for (auto _ : state) {
    run = CalibrateDataset(dir, options, {SemanticMode::kNone});
    benchmark::DoNotOptimize(run);
  }
  const RigCalibrationResult& result = run.results.at(0);
  const CalibrationReport& p = result.pairwise;
  state.counters["detect_s"] = run.records.at(0).detect_time_s;
  state.counters["screen_s"] = p.screen_time_s;
  state.counters["match_s"] = p.match_time_s + p.temporal_match_time_s;
  state.counters["pose_s"] = p.pose_time_s + p.temporal_pose_time_s;
  state.counters["rig_s"] = result.work.rotation_averaging_time_s + result.work.tracks_time_s + result.work.positions_time_s;
  state.counters["ba_s"] = result.work.bundle_adjustment_time_s;

  const CalibrationScores truth = ScorePoses(ReadRig(dir / "rig.json"), run.inputs.frames, result);
  double worst_rot = 0.0, worst_dir = 0.0;
  int calibrated = 0;
  for (size_t c = 0; c < truth.cameras.size(); ++c) {
    const CameraAgainstTruth& s = truth.cameras[c];
    calibrated += result.rig.cameras[c].cam_from_rig.has_value();
    worst_rot = std::max(worst_rot, s.rotation_error_deg.value_or(1e9));
    if (c > 0) worst_dir = std::max(worst_dir, s.translation_direction_error_deg.value_or(1e9));
  }
  state.counters["cameras_calibrated"] = calibrated;
  state.counters["worst_rot_deg"] = worst_rot;
  state.counters["worst_tdir_deg"] = worst_dir;
}
BENCHMARK(BM_CalibrateSixCameraRing)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(3);

}  // namespace
}  // namespace rigsim

BENCHMARK_MAIN();
