// What the calibration made of each camera, typed: its outcome, its position's, and why in words;
// and the kind of the result's unit of length.
#pragma once

#include <ostream>
#include <string>

namespace rigsim {

// What the calibration made of a camera.
enum class CameraOutcome {
  kCalibrated,    // a full pose (camera 0: the rig frame)
  // A full pose that holds only if the camera captured with camera 0: the synchronisation check
  // ran, and the rig's path moves alike at every frame, so it cannot show a time offset.
  kCalibratedIfSynchronised,
  kRotationOnly,  // a rotation, no position (CameraStatus::position says why)
  kNotConnected,  // no pair links it to camera 0's part of the view graph: no pose at all
  kUnsynchronised,  // it did not capture with camera 0 and offsets were not estimated: no pose
  kTimeNotDetermined,  // its offset was to be estimated and the rig's path cannot show it: no pose
  // A rotation and a position but for one component: a planar motion placed it and no point joins
  // it with another camera, so its offset along the turn axis is open (PositionOutcome::kOpenAlongTurnAxis;
  // RigCalibrationResult::partial_centre). No cam_from_rig in the rig: no made-up component.
  kOpenAlongAxis,
};

// The position of a camera with a rotation: placed, or why not.
enum class PositionOutcome {
  kPlaced,
  kNotObservable,  // nothing links its position to the placed cameras' (no start for it)
  kNotDetermined,  // the images fix its direction from camera 0 too loosely (max_direction_std_deg)
  kAmbiguous,      // starts adjusted apart, or its one pair fits a rival pose (rig_options.h)
  kOpenAlongTurnAxis,  // placed across the turn axis of a planar motion, open along it
};

struct CameraStatus {
  CameraOutcome outcome = CameraOutcome::kNotConnected;
  PositionOutcome position = PositionOutcome::kNotObservable;  // kPlaced when calibrated
  // Why, in words: for a rotation-only camera why it has no position and what would place it; for a
  // camera not connected its pairs with the connected cameras; "reference: rig frame" for camera 0.
  std::string reason;

  // The status as evaluation.json and the tables give it: "calibrated", "calibrated (reference:
  // rig frame)", "calibrated if synchronised: <reason>", "rotation only: position <reason>",
  // "placed but for one axis: <reason>" or "not connected: <reason>".
  std::string Text() const;
};
inline std::ostream& operator<<(std::ostream& os, const CameraStatus& s) { return os << s.Text(); }
// Whether the outcome gives the camera a full pose, unconditionally or if synchronised.
bool HasFullPose(CameraOutcome outcome);

// Images fix no scale: the result's unit of length is none (no camera placed besides camera 0),
// the distance of one camera from camera 0 (unit), or metres from a known distance (metric).
enum class ScaleKind { kNone, kUnit, kMetric };

}  // namespace rigsim
