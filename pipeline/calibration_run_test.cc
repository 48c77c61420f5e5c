#include "pipeline/calibration_run.h"

#include <filesystem>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "dataset/image_io.h"
#include "testing/expect_error.h"
#include "testing/rendered_yard.h"
#include "testing/temp_dir.h"

namespace rigsim {
namespace {

namespace fs = std::filesystem;

// The yard (testing/rendered_yard.h) as a rendered dataset: rig.json with the truth, frames.json,
// images, labels and depth.
void WriteYardDataset(const fs::path& dir) {
  const RenderedYard& yard = TwoCameraYard();
  FramesFile frames;
  frames.scene = "rendered yard";
  for (size_t f = 0; f < yard.rig_from_world.size(); ++f) {
    frames.frames.push_back({"00000" + std::to_string(f), yard.rig_from_world[f], 0.0});
  }
  fs::create_directories(dir);
  WriteRig(yard.rig, dir / "rig.json");
  WriteFrames(frames, dir / "frames.json");
  const DatasetLayout layout(dir);
  for (size_t c = 0; c < yard.rig.cameras.size(); ++c) {
    const std::string& cam = yard.rig.cameras[c].name;
    for (size_t f = 0; f < frames.frames.size(); ++f) {
      const std::string& frame = frames.frames[f].name;
      for (const fs::path& p : {layout.Image(cam, frame), layout.Label(cam, frame), layout.Depth(cam, frame)}) {
        fs::create_directories(p.parent_path());
      }
      WriteImage(layout.Image(cam, frame), yard.rgb[c][f]);
      WriteImage(layout.Label(cam, frame), yard.labels[c][f]);
      WriteImage(layout.Depth(cam, frame), yard.range[c][f]);
    }
  }
}

class CalibrateDatasetTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    scratch_ = new TempDir();
    dir_ = *scratch_ / "dataset";
    WriteYardDataset(dir_);
  }
  static void TearDownTestSuite() { delete scratch_; }
  static TempDir* scratch_;
  static fs::path dir_;  // the dataset
};
TempDir* CalibrateDatasetTest::scratch_ = nullptr;
fs::path CalibrateDatasetTest::dir_;

// Every mode calibrated from the same photos, and compared with the truth: pose errors, and the
// match precision against the range images.
TEST_F(CalibrateDatasetTest, EveryModeIsComparedWithTheTruth) {
  CalibrationRunOptions options;
  options.rig.known_distance = KnownDistance{"cam0", "cam1", Eigen::Vector3d(0.6, 0.05, 0.1).norm()};  // the yard's
  const std::vector<SemanticMode> modes(std::begin(kAllSemanticModes), std::end(kAllSemanticModes));
  const CalibrationRun run = CalibrateDataset(dir_, options, modes);
  ASSERT_EQ(run.results.size(), 4u);
  ASSERT_EQ(run.records.size(), 4u);
  EXPECT_TRUE(run.labels_used);
  for (size_t m = 0; m < modes.size(); ++m) {
    const RigCalibrationResult& r = run.results[m];
    SCOPED_TRACE(r.semantic_mode);
    EXPECT_EQ(r.semantic_mode, SemanticModeName(modes[m]));
    EXPECT_GT(run.records[m].detect_time_s, 0.0);
    const CalibrationScores* truth = run.Truth(m);
    ASSERT_NE(truth, nullptr);
    ASSERT_EQ(truth->pairs.size(), 1u);
    const PairResult& pr = r.pairwise.pairs[0];
    const PairAgainstTruth& pt = truth->pairs[0];
    ASSERT_TRUE(pr.two_view.success) << pr.two_view.failure_reason;
    ASSERT_TRUE(pt.rotation_error_deg && pt.translation_direction_error_deg);
    EXPECT_LT(*pt.rotation_error_deg, 0.3);
    EXPECT_LT(*pt.translation_direction_error_deg, 5.0);
    EXPECT_EQ(PairWithinTolerance(pr, &pt), true);
    ASSERT_TRUE(pt.match_precision.has_value());
    EXPECT_EQ(pt.matches_evaluated, pr.two_view.num_matches);
    EXPECT_GT(*pt.match_precision, 0.7);
    EXPECT_GT(pt.inlier_precision.value(), *pt.match_precision - 1e-9);
    EXPECT_TRUE(pt.cross_class_matches.has_value()) << "labels/ has the true classes";
    const CameraAgainstTruth& cam1 = truth->cameras[1];
    EXPECT_LT(cam1.rotation_error_deg.value(), 0.3);
    EXPECT_LT(cam1.translation_direction_error_deg.value(), 5.0);
    EXPECT_LT(cam1.position_error_m.value(), 0.06);  // metric: the known distance
    EXPECT_EQ(CameraWithinTolerance(&cam1), true);
    // The match image's verdicts are the match precision's, for the inliers it shows.
    ASSERT_EQ(run.records[m].inlier_samples.size(), 1u);
    const PairInlierSample& s = run.records[m].inlier_samples[0];
    EXPECT_EQ(s.pair, 0);
    EXPECT_EQ(s.correct.size(), s.points.size());
  }
}

// What a report shows of the matching (RigCalibrationOptions::keep_details) agrees with the
// counts of the comparison with the truth.
TEST_F(CalibrateDatasetTest, KeptMatchesAgreeWithTheTruthsCounts) {
  CalibrationRunOptions options;
  options.rig.keep_details = true;
  const CalibrationRun run = CalibrateDataset(dir_, options, {SemanticMode::kNone});
  const RigCalibrationResult& r = run.results[0];
  ASSERT_TRUE(r.details);
  const CalibrationScores* truth = run.Truth(0);
  ASSERT_NE(truth, nullptr);
  const PairwiseMatchData& md = r.details->matches;
  int evaluated = 0, correct = 0, inliers_correct = 0;
  for (size_t f = 0; f < md.matches[0].size(); ++f) {
    const std::vector<char>& ok = truth->match_correct[0][f];
    ASSERT_EQ(ok.size(), md.matches[0][f].size());
    evaluated += int(ok.size());
    for (size_t i = 0; i < ok.size(); ++i) {
      correct += ok[i];
      inliers_correct += ok[i] && md.match_inlier[0][f][i];
    }
  }
  EXPECT_EQ(evaluated, truth->pairs[0].matches_evaluated);
  EXPECT_EQ(correct, truth->pairs[0].matches_correct);
  EXPECT_EQ(inliers_correct, truth->pairs[0].inliers_correct);
}

TEST_F(CalibrateDatasetTest, WithoutEvaluationNothingIsComparedWithTheTruth) {
  CalibrationRunOptions options;
  options.evaluate = false;
  const CalibrationRun run = CalibrateDataset(dir_, options, {SemanticMode::kNone});
  EXPECT_EQ(run.Truth(0), nullptr);
  ASSERT_EQ(run.records[0].inlier_samples.size(), 1u);
  EXPECT_TRUE(run.records[0].inlier_samples[0].correct.empty());
}

TEST_F(CalibrateDatasetTest, MissingInputsAreNamed) {
  const TempDir scratch;
  const fs::path copy = scratch / "dataset";
  fs::copy(dir_, copy, fs::copy_options::recursive);
  const DatasetLayout layout(copy);
  fs::remove_all(copy / "labels");
  EXPECT_THAT([&] { CalibrateDataset(copy, {}, {SemanticMode::kMask}); },
              ThrowsWith<std::runtime_error>(layout.Label("cam0", "000000").filename().string()));
  fs::remove(*layout.FindImage("cam1", "000001"));
  EXPECT_THAT([&] { CalibrateDataset(copy, {}, {SemanticMode::kNone}); },
              ThrowsWith<std::runtime_error>("cam1", "000001"));
}

// Checked against rig.json before the long run, naming the file.
TEST_F(CalibrateDatasetTest, AKnownDistanceBetweenCamerasNotInTheRigIsRefused) {
  CalibrationRunOptions options;
  options.rig.known_distance = KnownDistance{"cam0", "cam9", 1.0};
  EXPECT_THAT([&] { CalibrateDataset(dir_, options, {SemanticMode::kNone}); },
              ThrowsWith<std::invalid_argument>((dir_ / "rig.json").string(), "cam9"));
}

TEST(WithGivenIntrinsics, ReplaceTheRigsByName) {
  Rig rig;
  rig.cameras.push_back({"a", Camera::PinholeFromHorizontalFov(640, 480, 90), Rigid3d(), 0.0});
  rig.cameras.push_back({"b", Camera::PinholeFromHorizontalFov(640, 480, 90), Rigid3d(), 0.0});
  Rig given;
  given.cameras.push_back({"b", Camera(CameraModelId::kPinhole, 640, 480, {330, 331, 320, 240}), std::nullopt, 0.0});
  given.cameras.push_back({"a", Camera(CameraModelId::kPinhole, 640, 480, {310, 311, 322, 242}), std::nullopt, 0.0});
  const Rig out = WithGivenIntrinsics(rig, given, "datasheet.json");
  EXPECT_EQ(out.cameras[0].camera.params(), given.cameras[1].camera.params());
  EXPECT_EQ(out.cameras[1].camera.params(), given.cameras[0].camera.params());
  EXPECT_TRUE(out.cameras[0].cam_from_rig.has_value()) << "the poses stay rig.json's";
  given.cameras.pop_back();
  EXPECT_THAT([&] { WithGivenIntrinsics(rig, given, "datasheet.json"); },
              ThrowsNaming<std::invalid_argument>("datasheet.json", "no camera 'a'"));
  given.cameras[0].camera = Camera(CameraModelId::kPinhole, 320, 240, {165, 165, 160, 120});
  given.cameras.push_back({"a", given.cameras[0].camera, std::nullopt, 0.0});
  EXPECT_THAT([&] { WithGivenIntrinsics(rig, given, "datasheet.json"); },
              ThrowsNaming<std::invalid_argument>("datasheet.json", "is 320x240"));
}

}  // namespace
}  // namespace rigsim
