#include "report/report_geometry.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "pipeline/calibration_scores.h"

namespace rigsim {

std::vector<Eigen::Vector3d> FieldOfViewOutline(const Camera& camera, int per_side) {
  const double w = camera.width(), h = camera.height();
  const Eigen::Vector2d centre(camera.cx(), camera.cy());
  // Clockwise from the top-left corner of the image rectangle [-0.5, w-0.5) x [-0.5, h-0.5).
  const Eigen::Vector2d corners[4] = {{-0.5, -0.5}, {w - 0.5, -0.5}, {w - 0.5, h - 0.5}, {-0.5, h - 0.5}};
  std::vector<Eigen::Vector3d> rays;
  for (int side = 0; side < 4; ++side) {
    for (int i = 0; i < per_side; ++i) {
      const double t = double(i) / per_side;
      const Eigen::Vector2d border = (1 - t) * corners[side] + t * corners[(side + 1) % 4];
      if (const auto ray = camera.CamFromImg(border)) {
        rays.push_back(*ray);
        continue;
      }
      // Bisect between the principal point (which has a ray) and the border pixel.
      double lo = 0.0, hi = 1.0;
      for (int it = 0; it < 40; ++it) {
        const double mid = 0.5 * (lo + hi);
        (camera.CamFromImg(centre + mid * (border - centre)) ? lo : hi) = mid;
      }
      if (const auto ray = camera.CamFromImg(centre + lo * (border - centre))) rays.push_back(*ray);
    }
  }
  return rays;
}

std::vector<double> EpipolarDepths(double nearest, double farthest, int count) {
  if (!(nearest > 0) || !(farthest > nearest) || count < 2) throw std::invalid_argument("EpipolarDepths: bad range");
  std::vector<double> depths;
  for (int i = 0; i < count; ++i) depths.push_back(nearest * std::pow(farthest / nearest, double(i) / (count - 1)));
  return depths;
}

std::vector<std::optional<Eigen::Vector2d>> EpipolarCurve(const Camera& cam_a, const Eigen::Vector2d& px_a,
                                                          const Camera& cam_b, const Rigid3d& b_from_a,
                                                          const std::vector<double>& depths) {
  std::vector<std::optional<Eigen::Vector2d>> curve;
  const auto ray = cam_a.CamFromImg(px_a);
  if (!ray) return curve;
  for (double d : depths) curve.push_back(cam_b.ImgFromCam(b_from_a * (*ray * d)));
  curve.push_back(cam_b.ImgFromCam(b_from_a.rotation * *ray));
  return curve;
}

AlignedEstimate AlignToTruth(const RigCalibrationResult& result, const Rig& truth, const FramesFile& frames) {
  if (!truth.HasAllPoses()) throw std::invalid_argument("AlignToTruth: the truth needs every camera's cam_from_rig");
  if (frames.frames.empty() || !frames.frames[0].rig_from_world) {
    throw std::invalid_argument("AlignToTruth: frame 0 needs its true rig_from_world");
  }
  AlignedEstimate a;
  const RigEstimate estimate = RigEstimateOf(result);
  a.scores = ScoreRig(truth, estimate);
  a.scale = a.scores.scale;
  const size_t n = truth.cameras.size();
  a.cam_from_cam0.assign(n, std::nullopt);
  a.rotation_only.assign(n, 0);
  const Rigid3d true_rig_from_cam0 = truth.cameras[0].cam_from_rig->Inverse();
  const std::optional<Rigid3d>& est_cam0 = estimate.cam_from_rig[0];
  if (est_cam0) {
    const Rigid3d est_rig_from_cam0 = est_cam0->Inverse();
    for (size_t c = 0; c < n && c < estimate.cam_from_rig.size(); ++c) {
      if (estimate.cam_from_rig[c]) {
        Rigid3d p = *estimate.cam_from_rig[c] * est_rig_from_cam0;
        p.translation *= a.scale;
        a.cam_from_cam0[c] = p;
      } else if (estimate.rotation_only[c]) {
        const Rigid3d truth_c = *truth.cameras[c].cam_from_rig * true_rig_from_cam0;
        const Eigen::Quaterniond r = *estimate.rotation_only[c] * est_cam0->rotation.inverse();
        // The true centre, seen with the estimated rotation: t = -R C.
        a.cam_from_cam0[c] = Rigid3d(r, -(r * truth_c.SourceOriginInTarget()));
        a.rotation_only[c] = 1;
      }
    }
  }
  // The estimate's world is camera 0 at frame 0 (rig_calibration.h): place it at the true one.
  const Rigid3d true_cam0_from_world = *truth.cameras[0].cam_from_rig * *frames.frames[0].rig_from_world;
  const Rigid3d world_from_cam0 = true_cam0_from_world.Inverse();
  a.world_rotation = world_from_cam0.rotation.toRotationMatrix();
  a.world_translation = world_from_cam0.translation;
  return a;
}

}  // namespace rigsim
