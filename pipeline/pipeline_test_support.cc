#include "pipeline/pipeline_test_support.h"

#include <string>
#include <utility>

namespace rigsim {
namespace {

Rigid3d Yaw(double deg, const Eigen::Vector3d& t) {
  return Rigid3d(Eigen::Quaterniond(Eigen::AngleAxisd(DegToRad(deg), Eigen::Vector3d::UnitY())), t);
}

Camera Pinhole() { return Camera(CameraModelId::kPinhole, 640, 480, {500, 500, 319.5, 239.5}); }

}  // namespace

RigCalibrationResult ThreeCameraResult() {
  RigCalibrationResult r;
  r.semantic_mode = "mask";
  r.rig.cameras = {{"cam0", Pinhole(), Rigid3d(), 0.0},
                   {"cam1", Pinhole(), Yaw(60, {-0.5, 0, 0.1}), 0.0},
                   {"cam2", Pinhole(), std::nullopt, 0.0}};
  r.cam_from_rig_rotation = {Eigen::Quaterniond::Identity(), Yaw(60, Eigen::Vector3d::Zero()).rotation,
                             Yaw(120, Eigen::Vector3d::Zero()).rotation};
  r.camera_status = {{CameraOutcome::kCalibrated, PositionOutcome::kPlaced, "reference: rig frame"},
                     {CameraOutcome::kCalibrated, PositionOutcome::kPlaced, ""},
                     {CameraOutcome::kRotationOnly, PositionOutcome::kNotObservable,
                      "not observable: too little parallax"}};
  r.camera_stats.assign(3, {});
  r.rig_from_world = {Rigid3d(), Yaw(5, {0, 0, -2})};
  r.scale = "unit scale: |centre of cam1| = 1";
  r.scale_kind = ScaleKind::kUnit;

  CalibrationReport& rep = r.pairwise;
  rep.num_cameras = 3;
  rep.num_frames = 3;
  auto pair = [](std::string a, std::string b, bool success, int matches, int inliers) {
    PairResult p;
    p.cam_a = std::move(a);
    p.cam_b = std::move(b);
    p.frames = 3;
    p.two_view.success = success;
    p.two_view.num_matches = matches;
    p.two_view.num_inliers = inliers;
    p.two_view.pair_type = PairType::kGeneral;
    if (success) p.two_view.cam_b_from_cam_a = Yaw(60, {-1, 0, 0});
    if (!success) p.two_view.failure_reason = "too few matches";
    return p;
  };
  rep.pairs = {pair("cam0", "cam1", true, 400, 300), pair("cam0", "cam2", false, 3, 0),
               pair("cam1", "cam2", true, 200, 20)};
  rep.pairs[2].two_view.pair_type = PairType::kPlanar;

  RigEdgeStats used;
  used.cam_a = "cam0";
  used.cam_b = "cam1";
  used.inliers = 300;
  used.outcome = EdgeOutcome::kUsed;
  used.rotation_residual_deg = 0.25;
  used.status = "used";
  RigEdgeStats failed;
  failed.cam_a = "cam0";
  failed.cam_b = "cam2";
  failed.outcome = EdgeOutcome::kTwoViewFailed;
  failed.status = "two-view failed: too few matches";
  r.edges = {used, failed};
  return r;
}

FramesFile ThreeFrames() {
  FramesFile f;
  for (const char* name : {"000000", "000001", "000002"}) f.frames.push_back({name, std::nullopt, 0.0});
  return f;
}

CalibrationRun RunOf(const std::vector<RigCalibrationResult>& results) {
  CalibrationRun run;
  run.inputs.rig = results.at(0).rig;
  run.inputs.frames = ThreeFrames();
  for (const RigCalibrationResult& r : results) run.modes.push_back(SemanticModeFromName(r.semantic_mode));
  run.results = results;
  run.records.resize(results.size());
  return run;
}

}  // namespace rigsim
