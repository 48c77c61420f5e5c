// The calibration's partial estimates of a rig, as the stages pass them on: one entry per camera
// or per frame, nullopt where that camera or frame has none (yet), e.g. a camera the view graph
// does not reach or a frame no temporal pair chains to frame 0. A stage fills in what it
// determines and leaves the rest empty; nothing is guessed to fill a gap.
#pragma once

#include <optional>
#include <vector>

#include "geometry/rigid3.h"

namespace rigsim {

// Indexed by camera (the rig's order): e.g. each camera's cam_from_rig.
template <class T>
using PerCamera = std::vector<std::optional<T>>;

// Indexed by frame (or by the step from frame k to k + 1): e.g. the rig's rig_from_world.
template <class T>
using PerFrame = std::vector<std::optional<T>>;

// The rig's poses as a stage leaves them, in one unit of length: cam_from_rig per camera (camera 0
// is the rig frame) and rig_from_world per frame (frame 0's rig frame is the world). A view's pose
// is cam_from_rig * rig_from_world; a view of a camera or frame without a pose has none.
struct RigPoses {
  PerCamera<Rigid3d> cam_from_rig;
  PerFrame<Rigid3d> rig_from_world;

  bool Posed(int camera, int frame) const {
    return camera >= 0 && frame >= 0 && camera < static_cast<int>(cam_from_rig.size()) &&
           frame < static_cast<int>(rig_from_world.size()) && cam_from_rig[camera] && rig_from_world[frame];
  }
  // cam_from_world of view (camera, frame); Posed(camera, frame) must hold.
  Rigid3d CamFromWorld(int camera, int frame) const { return *cam_from_rig[camera] * *rig_from_world[frame]; }
};

// Changes the unit of length of a rig estimate: the cameras' and the frames' translations.
inline void ScaleTranslations(double s, PerCamera<Rigid3d>* cam_from_rig, PerFrame<Rigid3d>* rig_from_world) {
  for (auto* poses : {cam_from_rig, rig_from_world}) {
    for (auto& p : *poses) {
      if (p) p->translation *= s;
    }
  }
}

}  // namespace rigsim
