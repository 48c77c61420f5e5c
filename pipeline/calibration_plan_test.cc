#include "pipeline/calibration_plan.h"

#include <filesystem>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "testing/expect_error.h"
#include "testing/temp_dir.h"

namespace rigsim {
namespace {

namespace fs = std::filesystem;

// A dataset of two posed cameras and three frames at `times`, with labels/ or without: what the plan
// reads. No photos: the plan does not look at them.
fs::path WriteDataset(const fs::path& dir, const std::vector<double>& times, bool labels) {
  Rig rig;
  rig.cameras.push_back({"cam0", Camera::PinholeFromHorizontalFov(64, 48, 90), Rigid3d(), 0.0});
  rig.cameras.push_back({"cam1", Camera::PinholeFromHorizontalFov(64, 48, 90), Rigid3d(), 0.0});
  FramesFile frames;
  for (size_t f = 0; f < times.size(); ++f) frames.frames.push_back({"00000" + std::to_string(f), Rigid3d(), times[f]});
  fs::create_directories(dir);
  WriteRig(rig, dir / "rig.json");
  WriteFrames(frames, dir / "frames.json");
  if (labels) fs::create_directories(dir / "labels");
  return dir;
}

CalibrationRequest RequestFor(const fs::path& dataset, const fs::path& out) {
  CalibrationRequest request;
  request.dataset = dataset;
  request.modes = {SemanticMode::kNone, SemanticMode::kMask};
  request.out = {out, "--out", "rigsim calibrate", {}, false};
  return request;
}

struct Warnings {
  std::vector<std::string> seen;
  std::function<void(const std::string&)> Sink() {
    return [this](const std::string& w) { seen.push_back(w); };
  }
};

TEST(PlanCalibration, AKnownDistanceNamingAnUnknownCameraIsRefusedBeforeAnythingIsWritten) {
  const TempDir tmp;
  const fs::path dataset = WriteDataset(tmp / "data", {0.0, 0.1, 0.2}, true);
  CalibrationRequest request = RequestFor(dataset, tmp / "out");
  request.options.rig.known_distance = KnownDistance{"cam0", "cam9", 0.5};
  Warnings warnings;
  EXPECT_THAT([&] { PlanCalibration(request, warnings.Sink()); },
              ThrowsWith<std::invalid_argument>("--known-distance: no camera 'cam9' in " + (dataset / "rig.json").string(),
                                                "its cameras are cam0, cam1"));
  EXPECT_FALSE(fs::exists(tmp / "out"));
  request.options.rig.known_distance = KnownDistance{"cam1", "cam0", 0.5};
  EXPECT_EQ(PlanCalibration(request, warnings.Sink()).modes.size(), 2u);
  EXPECT_FALSE(fs::exists(tmp / "out")) << "planning writes nothing";
}

// The same check when the pipeline is called without a plan (the report's way).
TEST(CalibrateDataset, AKnownDistanceNamingAnUnknownCameraIsRefusedInTheCommandLinesWords) {
  const TempDir tmp;
  const fs::path dataset = WriteDataset(tmp / "data", {0.0, 0.1, 0.2}, true);
  CalibrationRunOptions options;
  options.rig.known_distance = KnownDistance{"cam7", "cam1", 0.5};
  EXPECT_THAT([&] { CalibrateDataset(dataset, options, {SemanticMode::kNone}); },
              ThrowsWith<std::invalid_argument>("--known-distance: no camera 'cam7'"));
}

TEST(PlanCalibration, CaptureTimesNeedFramesAtDistinctTimes) {
  const TempDir tmp;
  const fs::path dataset = WriteDataset(tmp / "data", {0.0, 0.0, 0.0}, true);
  CalibrationRequest request = RequestFor(dataset, tmp / "out");
  request.options.rig.capture_time.estimate_readout = true;
  Warnings warnings;
  EXPECT_THAT([&] { PlanCalibration(request, warnings.Sink()); },
              ThrowsWith<std::invalid_argument>("--rolling-shutter: " + (dataset / "frames.json").string()));
  request.options.rig.capture_time.estimate_offsets = true;
  EXPECT_THAT([&] { PlanCalibration(request, warnings.Sink()); }, ThrowsWith<std::invalid_argument>("--estimate-time-offsets: "));
  EXPECT_FALSE(fs::exists(tmp / "out"));
}

TEST(PlanCalibration, ModesThatNeedLabelsAreDroppedWithAWarningOrRefusedWhenNamed) {
  const TempDir tmp;
  const fs::path dataset = WriteDataset(tmp / "data", {0.0, 0.1, 0.2}, false);
  CalibrationRequest request = RequestFor(dataset, tmp / "out");
  Warnings warnings;
  const CalibrationPlan plan = PlanCalibration(request, warnings.Sink());
  EXPECT_EQ(plan.modes, std::vector<SemanticMode>{SemanticMode::kNone});
  EXPECT_FALSE(plan.labels_used);
  ASSERT_EQ(warnings.seen.size(), 1u);
  EXPECT_THAT(warnings.seen[0], ::testing::HasSubstr("has no labels/: calibrating with --semantics none only (mask"));
  request.modes_given = true;
  EXPECT_THAT([&] { PlanCalibration(request, warnings.Sink()); },
              ThrowsWith<std::runtime_error>((dataset / "labels").string() + ": no such folder: --semantics mask"));
}

TEST(PlanCalibration, ANetworkIsOneLabelSourceAndIsNotLoadedWhenUnused) {
  const TempDir tmp;
  const fs::path dataset = WriteDataset(tmp / "data", {0.0, 0.1, 0.2}, true);
  CalibrationRequest request = RequestFor(dataset, tmp / "out");
  request.segmenter_model = tmp / "net.onnx";
  request.segmenter_options = []() -> SegmenterOptions { throw std::logic_error("the network's options were read"); };
  request.options.labels = LabelSource::Noisy({});
  Warnings warnings;
  EXPECT_THAT([&] { PlanCalibration(request, warnings.Sink()); },
              ThrowsWith<std::invalid_argument>("--segmenter and --labels noisy both say where the labels come from"));
  request.options.labels = LabelSource::Truth();
  request.modes = {SemanticMode::kNone};
  const CalibrationPlan plan = PlanCalibration(request, warnings.Sink());
  EXPECT_EQ(plan.segmenter, nullptr);
  ASSERT_EQ(warnings.seen.size(), 1u);
  EXPECT_EQ(warnings.seen[0], "--segmenter " + (tmp / "net.onnx").string() + " is not used: no semantic mode given needs labels");
  // A network that is used is loaded before anything is written: a missing model file stops the plan.
  request.modes = {SemanticMode::kMask};
  request.segmenter_options = [&] {
    SegmenterOptions o;
    o.model = tmp / "net.onnx";
    return o;
  };
  EXPECT_THAT([&] { PlanCalibration(request, warnings.Sink()); }, ThrowsWith<std::runtime_error>("no such model file"));
  EXPECT_FALSE(fs::exists(tmp / "out"));
}

TEST(LabelSourceNamed, TruthNoisyOrAFolder) {
  const TempDir tmp;
  EXPECT_EQ(LabelSourceNamed("truth", {}).kind, LabelSource::Kind::kTruth);
  SegmentationNoiseOptions noise;
  noise.seed = 7;
  const LabelSource noisy = LabelSourceNamed("noisy", noise, "--label-noise-seed");
  EXPECT_EQ(noisy.kind, LabelSource::Kind::kNoisy);
  EXPECT_EQ(noisy.noise.seed, 7u);
  EXPECT_EQ(LabelSourceNamed(tmp.string(), {}).folder, tmp.path());
  EXPECT_THAT([&] { LabelSourceNamed("truth", {}, "--label-noise-seed"); },
              ThrowsExactly<std::invalid_argument>("--label-noise-seed needs --labels noisy (got --labels truth)"));
  EXPECT_THAT([&] { LabelSourceNamed("", {}); }, ThrowsWith<std::invalid_argument>("--labels: give truth, noisy or a folder"));
  EXPECT_THAT([&] { LabelSourceNamed((tmp / "none").string(), {}); }, ThrowsWith<std::runtime_error>((tmp / "none").string()));
}

}  // namespace
}  // namespace rigsim
