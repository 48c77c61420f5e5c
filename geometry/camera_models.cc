#include "geometry/camera_models.h"

#include <stdexcept>

namespace rigsim {

std::string_view CameraModelName(CameraModelId id) {
  switch (id) {
    case CameraModelId::kPinhole: return "PINHOLE";
    case CameraModelId::kOpenCV: return "OPENCV";
    case CameraModelId::kFullOpenCV: return "FULL_OPENCV";
    case CameraModelId::kOpenCVFisheye: return "OPENCV_FISHEYE";
  }
  return "UNKNOWN";
}

CameraModelId CameraModelFromName(std::string_view name) {
  for (CameraModelId id : kAllCameraModels) {
    if (CameraModelName(id) == name) return id;
  }
  throw std::invalid_argument("unknown camera model '" + std::string(name) +
                              "' (expected PINHOLE, OPENCV, FULL_OPENCV or OPENCV_FISHEYE)");
}

int CameraModelNumParams(CameraModelId id) {
  switch (id) {
    case CameraModelId::kPinhole: return 4;
    case CameraModelId::kOpenCV: return 8;
    case CameraModelId::kFullOpenCV: return 12;
    case CameraModelId::kOpenCVFisheye: return 8;
  }
  return 0;
}

std::string_view CameraModelParamNames(CameraModelId id) {
  switch (id) {
    case CameraModelId::kPinhole: return "fx fy cx cy";
    case CameraModelId::kOpenCV: return "fx fy cx cy k1 k2 p1 p2";
    case CameraModelId::kFullOpenCV: return "fx fy cx cy k1 k2 p1 p2 k3 k4 k5 k6";
    case CameraModelId::kOpenCVFisheye: return "fx fy cx cy k1 k2 k3 k4";
  }
  return "";
}

bool IsFisheyeModel(CameraModelId id) { return id == CameraModelId::kOpenCVFisheye; }

}  // namespace rigsim
