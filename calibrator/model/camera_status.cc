#include "calibrator/model/camera_status.h"

namespace rigsim {

std::string CameraStatus::Text() const {
  switch (outcome) {
    case CameraOutcome::kCalibrated: return reason.empty() ? "calibrated" : "calibrated (" + reason + ")";
    case CameraOutcome::kCalibratedIfSynchronised: return "calibrated if synchronised: " + reason;
    case CameraOutcome::kRotationOnly: return "rotation only: position " + reason;
    case CameraOutcome::kNotConnected: return "not connected: " + reason;
    case CameraOutcome::kUnsynchronised:
    case CameraOutcome::kTimeNotDetermined: return "not calibrated: " + reason;
    case CameraOutcome::kOpenAlongAxis: return "placed but for one axis: " + reason;
  }
  return reason;
}

bool HasFullPose(CameraOutcome outcome) {
  return outcome == CameraOutcome::kCalibrated || outcome == CameraOutcome::kCalibratedIfSynchronised;
}

}  // namespace rigsim
