// A small mixed rig and two frames shared by the export tests.
#pragma once

#include "dataset/dataset.h"
#include "geometry/rig.h"

namespace rigsim::test {

inline Rigid3d Pose(double ax, double ay, double az, const Eigen::Vector3d& t) {
  const Eigen::Quaterniond q = Eigen::AngleAxisd(ax, Eigen::Vector3d::UnitX()) * Eigen::AngleAxisd(ay, Eigen::Vector3d::UnitY()) *
                               Eigen::AngleAxisd(az, Eigen::Vector3d::UnitZ());
  return Rigid3d(q, t);
}

// cam0 OPENCV, cam1 PINHOLE, cam2 OPENCV_FISHEYE, all with non-trivial cam_from_rig.
inline Rig MixedRig() {
  Rig rig;
  rig.cameras.push_back({"cam0", Camera(CameraModelId::kOpenCV, 640, 480, {500, 510, 319.5, 239.5, -0.2, 0.05, 0.001, -0.002}),
                         Pose(0.1, -0.3, 0.05, {0.1, 0.0, 0.02}), 0.0});
  rig.cameras.push_back({"cam1", Camera(CameraModelId::kPinhole, 800, 600, {600, 600, 401.0, 298.0}),
                         Pose(-0.05, 0.4, 0.0, {-0.2, 0.01, 0.0}), 0.0});
  rig.cameras.push_back({"cam2", Camera(CameraModelId::kOpenCVFisheye, 1024, 1024, {300, 300, 511.5, 511.5, 0.01, -0.02, 0.003, -0.001}),
                         Pose(0.0, 1.6, 0.1, {0.0, 0.3, -0.5}), 0.0});
  return rig;
}

inline FramesFile TwoFrames() {
  FramesFile f;
  f.frames.push_back({"000000", Pose(0.02, 0.5, 0.0, {1.0, -1.6, 3.0}), 0.0});
  f.frames.push_back({"000001", Pose(0.0, 0.7, -0.01, {1.5, -1.6, 2.0}), 0.1});
  return f;
}

}  // namespace rigsim::test
