#include "calibrator/capture_time.h"

#include <cmath>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "calibrator/calibrator_test_support.h"
#include "testing/synthetic_rig.h"

namespace rigsim {
namespace {

// A path that turns at a changing rate and pitches: capture times show in the images.
std::vector<Rigid3d> VariedPath() { return TurningPath(6, 1.5, 8.0, 1.5, 3.0, 2.0); }

std::vector<char> TopToBottom() { return {}; }

TEST(CheckSynchronisation, FindsCamerasThatDidNotCaptureWithCameraZero) {
  const TimedRing ring(VariedPath(), 0.3, TestSeed(), {0.0, 0.030, 0.060}, {0.0, 0.0, 0.0});
  const MultiFrameBundleAdjustmentResult taken_as_synchronised = ring.Adjust(nullptr);
  const std::vector<CameraSynchronisation> verdict =
      CheckSynchronisation(ring.cameras, ring.s.keypoints, ring.tracks, taken_as_synchronised, 1, {},
                           ring.timing.frame_times_s, {0.0, 0.0, 0.0}, TopToBottom(), {});
  ASSERT_EQ(verdict.size(), 3u);
  EXPECT_FALSE(verdict[0].unsynchronised);
  for (int c = 1; c < 3; ++c) {
    EXPECT_TRUE(verdict[c].unsynchronised) << c;
    ASSERT_TRUE(verdict[c].offset_s && verdict[c].offset_stddev_s) << c;
    EXPECT_NEAR(*verdict[c].offset_s, 0.030 * c, 3 * *verdict[c].offset_stddev_s + 1e-4) << c;
  }
}

TEST(CheckSynchronisation, ASynchronisedRigPasses) {
  const TimedRing ring(VariedPath(), 0.3, TestSeed(), {0.0, 0.0, 0.0}, {0.0, 0.0, 0.0});
  const std::vector<CameraSynchronisation> verdict =
      CheckSynchronisation(ring.cameras, ring.s.keypoints, ring.tracks, ring.Adjust(nullptr), 1, {},
                           ring.timing.frame_times_s, {0.0, 0.0, 0.0}, TopToBottom(), {});
  for (int c = 1; c < 3; ++c) {
    EXPECT_FALSE(verdict[c].unsynchronised) << c;
    ASSERT_TRUE(verdict[c].offset_s) << c;
    EXPECT_LT(std::abs(*verdict[c].offset_s), 0.002) << c;
  }
}

TEST(StartTimeOffsets, ComesFromEachCameraOwnTurns) {
  SyntheticRigOptions o;
  o.cameras.assign(3, Camera(CameraModelId::kPinhole, 640, 480, {300, 300, 319.5, 239.5}));
  o.ring_radius_m = 0.3;
  o.yaw_step_deg = 45.0;
  o.num_frames = 8;
  o.path = TurningPath(8, 1.5, 10.0, 1.5, 0.0, 0.0);
  o.num_points = 1500;
  o.noise_px = 0.3;
  o.time_offset_s = {0.0, 0.040, -0.030};
  o.seed = TestSeed();
  SyntheticRig s = SynthesizeRig(o);
  SyntheticObservationOptions observe;
  observe.temporal_pairs = true;
  const RigObservations obs = ObserveSyntheticRig(s, observe);
  std::vector<double> times;
  for (int k = 0; k < o.num_frames; ++k) times.push_back(k * o.frame_interval_s);
  const std::vector<double> start = StartTimeOffsets(3, times, obs.temporal, {});
  EXPECT_EQ(start[0], 0.0);
  EXPECT_NEAR(start[1], 0.040, 0.008);
  EXPECT_NEAR(start[2], -0.030, 0.008);
}

TEST(WhyNoTimingModel, NamesWhatIsMissing) {
  EXPECT_TRUE(WhyNoTimingModel({0.0, 0.1}));
  EXPECT_TRUE(WhyNoTimingModel({0.0, 0.1, 0.1}));
  EXPECT_FALSE(WhyNoTimingModel({0.0, 0.1, 0.2}));
}

}  // namespace
}  // namespace rigsim

namespace rigsim {
namespace {

// The whole rig stage on a ring whose cameras capture 30 and 60 ms after camera 0 along a path
// that turns at a changing rate: taken as synchronised the two are not calibrated, and with the
// offsets estimated every camera is placed and its offset found within its standard deviation.
struct UnsynchronisedRing {
  RigObservations obs;
  std::vector<double> offsets = {0.0, 0.020, 0.040};
  UnsynchronisedRing() {
    SyntheticRigOptions o;
    o.cameras.assign(3, Camera(CameraModelId::kPinhole, 640, 480, {300, 300, 319.5, 239.5}));
    o.ring_radius_m = 0.3;
    o.yaw_step_deg = 45.0;
    o.num_frames = 6;
    o.path = TurningPath(6, 0.4, 5.0, 1.5, 2.0, 1.0);  // 4 m/s
    o.num_points = 1500;
    o.noise_px = 0.3;
    o.time_offset_s = offsets;
    o.seed = TestSeed();
    SyntheticRig s = SynthesizeRig(o);
    SyntheticObservationOptions observe;
    observe.temporal_pairs = true;
    obs = ObserveSyntheticRig(s, observe);
    for (int k = 0; k < o.num_frames; ++k) obs.frame_times_s.push_back(k * o.frame_interval_s);
  }
};

TEST(EstimateRigWithCaptureTimes, UnsynchronisedCamerasAreNotCalibratedUnlessTheirOffsetsAreEstimated) {
  const UnsynchronisedRing ring;
  RigCalibrationOptions checked;
  checked.capture_time.check_synchronisation = true;
  const RigCalibrationResult taken_as_synchronised = EstimateRig(ring.obs, checked);
  for (int c = 1; c < 3; ++c) {
    EXPECT_EQ(taken_as_synchronised.camera_status[c].outcome, CameraOutcome::kUnsynchronised)
        << taken_as_synchronised.camera_status[c];
    EXPECT_FALSE(taken_as_synchronised.rig.cameras[c].cam_from_rig);
  }
  RigCalibrationOptions options;
  options.capture_time.estimate_offsets = true;
  const RigCalibrationResult estimated = EstimateRig(ring.obs, options);
  for (int c = 1; c < 3; ++c) {
    EXPECT_EQ(estimated.camera_status[c].outcome, CameraOutcome::kCalibrated) << estimated.camera_status[c];
    const RigCameraStats& s = estimated.camera_stats[c];
    ASSERT_TRUE(s.time_offset_s && s.time_offset_stddev_s) << c;
    EXPECT_NEAR(*s.time_offset_s, ring.offsets[c], 3 * *s.time_offset_stddev_s + 1e-4) << c;
    EXPECT_NEAR(estimated.rig.cameras[c].time_offset_s, ring.offsets[c], 0.002) << c;
  }
}

TEST(EstimateRigWithCaptureTimes, FramesWithoutDistinctTimesAreRefused) {
  UnsynchronisedRing ring;
  ring.obs.frame_times_s.assign(ring.obs.frame_times_s.size(), 0.0);
  RigCalibrationOptions options;
  options.capture_time.estimate_offsets = true;
  EXPECT_THROW(EstimateRig(ring.obs, options), std::invalid_argument);
  options.capture_time.estimate_offsets = false;  // the check needs the times: taken as synchronised
  const RigCalibrationResult unchecked = EstimateRig(ring.obs, options);
  for (const CameraStatus& status : unchecked.camera_status) EXPECT_NE(status.outcome, CameraOutcome::kUnsynchronised);
}

}  // namespace
}  // namespace rigsim
