// The calibration's partial estimates of a rig, as the stages pass them on: one entry per camera
// or per frame, nullopt where that camera or frame has none (yet), e.g. a camera the view graph
// does not reach or a frame no temporal pair chains to frame 0. A stage fills in what it
// determines and leaves the rest empty; nothing is guessed to fill a gap.
#pragma once

#include <optional>
#include <vector>

namespace rigsim {

// Indexed by camera (the rig's order): e.g. each camera's cam_from_rig.
template <class T>
using PerCamera = std::vector<std::optional<T>>;

// Indexed by frame (or by the step from frame k to k + 1): e.g. the rig's rig_from_world.
template <class T>
using PerFrame = std::vector<std::optional<T>>;

}  // namespace rigsim
