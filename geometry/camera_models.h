// Camera models: projection of a point in the camera frame to pixels, templated on the scalar
// type so that Ceres autodiff runs the very code the renderer uses.
//
// Conventions:
//   Camera frame: x right, y down, z forward.
//   Pixels: OpenCV's. The centre of the top-left pixel is (0, 0); the image covers
//   [-0.5, width - 0.5) x [-0.5, height - 0.5). (COLMAP puts that centre at (0.5, 0.5): exports
//   to COLMAP add 0.5 to cx, cy.)
//   Parameter names and orders are COLMAP's / OpenCV's:
//     PINHOLE         fx fy cx cy
//     OPENCV          fx fy cx cy k1 k2 p1 p2
//     FULL_OPENCV     fx fy cx cy k1 k2 p1 p2 k3 k4 k5 k6
//     OPENCV_FISHEYE  fx fy cx cy k1 k2 k3 k4   (Kannala-Brandt, equidistant; valid beyond 180 deg)
//   Distortion of the perspective models acts on normalised coordinates (x/z, y/z) exactly as
//   cv::projectPoints does; the fisheye model acts on theta = angle from the optical axis exactly
//   as cv::fisheye::projectPoints does.
#pragma once

#include <array>
#include <cmath>
#include <string>
#include <string_view>

namespace rigsim {

enum class CameraModelId { kPinhole, kOpenCV, kFullOpenCV, kOpenCVFisheye };

inline constexpr std::array<CameraModelId, 4> kAllCameraModels = {
    CameraModelId::kPinhole, CameraModelId::kOpenCV, CameraModelId::kFullOpenCV, CameraModelId::kOpenCVFisheye};

std::string_view CameraModelName(CameraModelId id);
// Throws std::invalid_argument naming the accepted models when `name` is unknown.
CameraModelId CameraModelFromName(std::string_view name);
int CameraModelNumParams(CameraModelId id);
std::string_view CameraModelParamNames(CameraModelId id);
bool IsFisheyeModel(CameraModelId id);

// Applies the lens distortion of a perspective model to normalised coordinates (u, v).
// `dist` points at the distortion parameters (params + 4).
template <typename T>
void DistortNormalized(CameraModelId id, const T* dist, const T& u, const T& v, T* ud, T* vd) {
  const T u2 = u * u, v2 = v * v, uv = u * v, r2 = u2 + v2;
  switch (id) {
    case CameraModelId::kPinhole:
      *ud = u;
      *vd = v;
      return;
    case CameraModelId::kOpenCV: {
      const T& k1 = dist[0]; const T& k2 = dist[1]; const T& p1 = dist[2]; const T& p2 = dist[3];
      const T radial = T(1) + r2 * (k1 + k2 * r2);
      *ud = u * radial + T(2) * p1 * uv + p2 * (r2 + T(2) * u2);
      *vd = v * radial + p1 * (r2 + T(2) * v2) + T(2) * p2 * uv;
      return;
    }
    case CameraModelId::kFullOpenCV: {
      const T& k1 = dist[0]; const T& k2 = dist[1]; const T& p1 = dist[2]; const T& p2 = dist[3];
      const T& k3 = dist[4]; const T& k4 = dist[5]; const T& k5 = dist[6]; const T& k6 = dist[7];
      const T r4 = r2 * r2, r6 = r4 * r2;
      const T radial = (T(1) + k1 * r2 + k2 * r4 + k3 * r6) / (T(1) + k4 * r2 + k5 * r4 + k6 * r6);
      *ud = u * radial + T(2) * p1 * uv + p2 * (r2 + T(2) * u2);
      *vd = v * radial + p1 * (r2 + T(2) * v2) + T(2) * p2 * uv;
      return;
    }
    case CameraModelId::kOpenCVFisheye:
      break;  // not a perspective model; handled by FisheyeDistortedTheta
  }
  *ud = u;
  *vd = v;
}

// Kannala-Brandt: theta_d = theta (1 + k1 theta^2 + k2 theta^4 + k3 theta^6 + k4 theta^8).
template <typename T>
T FisheyeDistortedTheta(const T* dist, const T& theta) {
  const T t2 = theta * theta;
  return theta * (T(1) + t2 * (dist[0] + t2 * (dist[1] + t2 * (dist[2] + t2 * dist[3]))));
}

// Projects a point in the camera frame to pixel coordinates. Returns false when the point has
// no image under the model's algebra (behind a perspective camera, on the optical axis at the
// camera centre). It does not check the lens's valid field of view: Camera does that.
template <typename T>
bool ImgFromCam(CameraModelId id, const T* params, const T* x_in_cam, T* px) {
  using std::atan2;
  using std::sqrt;
  const T& fx = params[0]; const T& fy = params[1]; const T& cx = params[2]; const T& cy = params[3];
  const T& x = x_in_cam[0]; const T& y = x_in_cam[1]; const T& z = x_in_cam[2];
  T ud, vd;
  if (id == CameraModelId::kOpenCVFisheye) {
    const T r2 = x * x + y * y;
    if (r2 == T(0)) {
      if (!(z > T(0))) return false;
      ud = T(0) * x;  // keep derivative structure for jets
      vd = T(0) * y;
    } else {
      const T r = sqrt(r2);
      const T theta = atan2(r, z);
      const T scale = FisheyeDistortedTheta(params + 4, theta) / r;
      ud = x * scale;
      vd = y * scale;
    }
  } else {
    if (!(z > T(0))) return false;
    DistortNormalized(id, params + 4, T(x / z), T(y / z), &ud, &vd);
  }
  px[0] = fx * ud + cx;
  px[1] = fy * vd + cy;
  return true;
}

}  // namespace rigsim
