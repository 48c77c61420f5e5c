// A rendered ring whose cameras capture 10, 20 and 30 ms after camera 0 while the rig drives a
// turn at a changing speed, through the real pipeline: the truth judges every view where its camera
// was when it captured (match precision), the calibration taken as synchronised places no camera
// outside tolerance, and with the offsets estimated it places every camera and finds the offsets.
#include <filesystem>

#include <gtest/gtest.h>

#include "evaluation/verdicts.h"
#include "gltf/gltf_loader.h"
#include "pipeline/calibration_run.h"
#include "renderer/render_dataset.h"
#include "rigs/rig_presets.h"
#include "rigs/trajectories.h"
#include "testing/temp_dir.h"

namespace rigsim {
namespace {

const std::vector<double> kOffsets = {0.0, 0.010, 0.020, 0.030};

class UnsynchronisedRig : public testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir();
    const Scene street = LoadGltf("assets/scenes/street.glb");
    RingRigOptions ring;
    ring.width = 640;
    ring.height = 360;
    Rig rig = MakeRingRig(ring);
    for (size_t c = 0; c < rig.cameras.size(); ++c) rig.cameras[c].time_offset_s = kOffsets[c];
    // The demo's turn, driven slower and faster in turn: 2 m per frame, 0.1 to 0.2 s apart.
    FramesFile frames = MakeDemoTrajectory(6);
    const double times[] = {0.0, 0.1, 0.3, 0.4, 0.6, 0.7};
    for (size_t k = 0; k < frames.frames.size(); ++k) frames.frames[k].timestamp_s = times[k];
    RenderJob job;
    job.options.samples_per_pixel = 1;
    job.scene = &street;
    job.scene_name = street.source;
    job.rig = rig;
    job.frames = frames;
    RenderDataset(job, *dir_, true);
  }
  static void TearDownTestSuite() { delete dir_; }
  static CalibrationRun Calibrate(bool estimate_offsets) {
    CalibrationRunOptions options;
    options.rig.capture_time.estimate_offsets = estimate_offsets;
    return CalibrateDataset(dir_->path(), options, {SemanticMode::kNone});
  }
  static TempDir* dir_;
};
TempDir* UnsynchronisedRig::dir_ = nullptr;

TEST_F(UnsynchronisedRig, TakenAsSynchronisedNothingIsCalibratedOutsideTolerance) {
  const CalibrationRun run = Calibrate(false);
  const RigCalibrationResult& r = run.results.at(0);
  const CalibrationScores* truth = run.Truth(0);
  ASSERT_NE(truth, nullptr);
  // Judged at capture time, matches between cameras 25 ms apart are as right as a synchronised
  // rig's (judged at the frames' times they would nearly all be wrong).
  const auto precision = PoolMatchPrecision(*truth).Precision();
  ASSERT_TRUE(precision.has_value());
  EXPECT_GT(*precision, 0.5);
  int unsynchronised = 0;
  for (size_t c = 1; c < kOffsets.size(); ++c) {
    const CameraAgainstTruth& e = truth->cameras[c];
    if (r.camera_status[c].outcome == CameraOutcome::kUnsynchronised) {
      ++unsynchronised;
      EXPECT_FALSE(r.rig.cameras[c].cam_from_rig);
      ASSERT_TRUE(e.time_offset_error_s.has_value()) << c;  // what the check measured
      EXPECT_LT(std::abs(*e.time_offset_error_s), 0.001) << "cam" << c;
      continue;
    }
    if (!r.rig.cameras[c].cam_from_rig) continue;
    EXPECT_TRUE(WithinTolerance(e.rotation_error_deg, e.translation_direction_error_deg, kCameraTolerance).value_or(false))
        << "cam" << c << " is " << r.camera_status[c];
  }
  EXPECT_EQ(unsynchronised, 3);  // on this path even 10 ms shows
  // A pair is judged against its relative pose at its cameras' capture times, as it saw it. Its
  // direction is allowed twice a pair's tolerance: cam1-cam2's came out within 5 deg from one
  // machine's renders and 5.35 deg from another's (BENCHMARKS.md).
  constexpr PoseTolerance kPairAtCaptureTimes{kPairTolerance.rotation_deg, 2 * kPairTolerance.direction_deg};
  for (size_t p = 0; p < r.pairwise.pairs.size(); ++p) {
    if (!r.pairwise.pairs[p].two_view.success) continue;
    const PairAgainstTruth& e = truth->pairs[p];
    EXPECT_TRUE(WithinTolerance(e.rotation_error_deg, e.translation_direction_error_deg, kPairAtCaptureTimes).value_or(false))
        << r.pairwise.pairs[p].cam_a << "-" << r.pairwise.pairs[p].cam_b << ": " << e.rotation_error_deg.value_or(-1)
        << " deg, " << e.translation_direction_error_deg.value_or(-1) << " deg";
  }
}

TEST_F(UnsynchronisedRig, EstimatedOffsetsPlaceEveryCamera) {
  const CalibrationRun run = Calibrate(true);
  const RigCalibrationResult& r = run.results.at(0);
  const CalibrationScores* truth = run.Truth(0);
  ASSERT_NE(truth, nullptr);
  for (size_t c = 1; c < kOffsets.size(); ++c) {
    const CameraAgainstTruth& e = truth->cameras[c];
    EXPECT_EQ(r.camera_status[c].outcome, CameraOutcome::kCalibrated) << "cam" << c << ": " << r.camera_status[c];
    EXPECT_TRUE(WithinTolerance(e.rotation_error_deg, e.translation_direction_error_deg, kCameraTolerance).value_or(false))
        << "cam" << c;
    ASSERT_TRUE(e.time_offset_error_s.has_value()) << c;
    EXPECT_LT(std::abs(*e.time_offset_error_s), 0.001) << "cam" << c;
  }
}

}  // namespace
}  // namespace rigsim
