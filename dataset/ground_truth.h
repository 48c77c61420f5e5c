// Ground-truth correspondence between two rendered views from their range images: where does
// the surface seen at a pixel of camera A appear in camera B, and is it visible there?
// Used for the ground-truth overlap (renderer) and for match precision (calibrator).
#pragma once

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "geometry/camera.h"
#include "geometry/image.h"
#include "geometry/rigid3.h"

namespace rigsim {

struct DepthTransferOptions {
  // Surface at B's pixel must agree with the transferred point's range within
  // max(abs_tolerance_m, rel_tolerance * range) to count as visible (not occluded).
  double abs_tolerance_m = 0.05;
  double rel_tolerance = 0.02;
};

// Range of a range image at a sub-pixel position (nearest pixel; 0 when outside or no surface).
float RangeAt(const ImageF& range, const Eigen::Vector2d& px);

// Transfers pixel `px_a` of camera A (with its range image) to camera B. Returns B's pixel when
// the surface point projects inside B's image and is not occluded in B's range image.
std::optional<Eigen::Vector2d> TransferPixel(const Eigen::Vector2d& px_a, const Camera& cam_a, const ImageF& range_a,
                                             const Camera& cam_b, const ImageF& range_b, const Rigid3d& b_from_a,
                                             const DepthTransferOptions& options = {});

// A view that camera A's surface points are transferred to: its camera and range image, and
// its pose relative to A.
struct TransferTarget {
  const Camera* camera = nullptr;
  const ImageF* range = nullptr;
  Rigid3d b_from_a;
};

// Over rows [y_begin, y_end) of A's range image: how many pixels see a surface, and how many of
// those are visible (depth-tested) in each target. Each pixel's ray is computed once for all the
// targets: undistorting it is most of the cost. `bearings_a`, when given, are A's pixel-centre
// rays already computed (row-major unit vectors, as Renderer::PixelCentreBearings gives them).
struct CoVisibleCounts {
  size_t surface = 0;
  std::vector<size_t> visible;  // per target
};
CoVisibleCounts CountCoVisible(const Camera& cam_a, const ImageF& range_a, const std::vector<TransferTarget>& targets,
                               int y_begin, int y_end, const DepthTransferOptions& options = {},
                               const std::vector<Eigen::Vector3f>* bearings_a = nullptr);

// A rendered view's pose: cam_from_world of every image row (a rolling shutter, each row captured
// from where the camera was at its time), or one for all rows.
struct ViewPose {
  std::vector<Rigid3d> cam_from_world_rows;  // 1 or the image height

  const Rigid3d& Row(int y) const { return cam_from_world_rows.size() == 1 ? cam_from_world_rows[0] : cam_from_world_rows[size_t(y)]; }
  bool Rolling() const { return cam_from_world_rows.size() > 1; }
};

// Where a world point appears in a view: its pixel, and the point in the camera frame of the row
// that sees it. With a rolling shutter the row is found by fixed-point iteration (project with a
// row's pose, take the row it lands on, until it lands on that row; at most 8 steps). nullopt when
// the camera model does not project it (behind, outside the lens's valid region).
struct ViewProjection {
  Eigen::Vector2d px;
  Eigen::Vector3d x_in_cam;
};
std::optional<ViewProjection> ProjectIntoView(const Eigen::Vector3d& x_in_world, const Camera& camera, const ViewPose& pose,
                                              int first_row_guess = -1);

// TransferPixel between two views, each posed at its capture time: A's point is lifted from A's
// pose at px_a's row and projected into B at the row that sees it (ProjectIntoView), so two cameras
// that capture while the rig moves, or rolling shutters, are checked where they were. The surface
// is taken as static between the two captures.
std::optional<Eigen::Vector2d> TransferPixel(const Eigen::Vector2d& px_a, const Camera& cam_a, const ImageF& range_a,
                                             const ViewPose& pose_a, const Camera& cam_b, const ImageF& range_b,
                                             const ViewPose& pose_b, const DepthTransferOptions& options = {});

// The image row (clamped into the image) of a pixel: the row whose pose captured it.
int RowOfPixel(const Eigen::Vector2d& px, const Camera& camera);

// Ground-truth correspondence from view A to view B (another camera, or the same camera at
// another frame: optical flow). Per pixel of A, 3 channels: x, y = where the surface point seen at
// A's pixel centre (lifted by its range along the pixel's ray, from A's pose at the pixel's row)
// projects in B (OpenCV pixel convention, possibly outside B's image), visible = 1 when it lies in
// B's image and B's range image sees that surface there (the depth test of the overlap), else 0.
// x = y = NaN where A sees no surface or B's camera does not project the point. The surface is
// taken as static between A's and B's capture times. `surface` and `visible` count A's surface
// pixels and those visible in B: for global shutters exactly CountCoVisible's figures.
struct CorrespondenceMap {
  ImageF map;  // 3 channels: x, y, visible
  size_t surface = 0, visible = 0;
};
CorrespondenceMap ComputeCorrespondence(const Camera& cam_a, const ImageF& range_a, const ViewPose& pose_a,
                                        const std::vector<Eigen::Vector3f>& bearings_a, const Camera& cam_b,
                                        const ImageF& range_b, const ViewPose& pose_b,
                                        const DepthTransferOptions& options = {});

// Fraction of A's pixels with a surface that are visible in B (depth-tested).
double CoVisibleFraction(const Camera& cam_a, const ImageF& range_a, const Camera& cam_b, const ImageF& range_b,
                         const Rigid3d& b_from_a, const DepthTransferOptions& options = {});

}  // namespace rigsim
