// A rig seen from above, as an SVG a person can open in any browser: each camera's centre, viewing
// direction and horizontal field of view, the estimate against the truth.
//
// Frame: the first camera's (x right, z forward), the gauge of `rigsim calibrate`; the truth is
// brought into it (truth_cam_from_cam0 = cam_from_rig * cam0_from_rig^-1). The page shows x to the
// right and z up, which is the view from above when the first camera's y points down.
// Scale: a unit-scale estimate is scaled to the truth (least squares over the cameras with both
// positions); a metric one, or one without truth, is drawn as it is.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "geometry/rig.h"

namespace rigsim {

struct RigPlotInput {
  std::string title;
  Rig estimate;  // cam_from_rig of the calibrated cameras (nullopt: no position)
  // Per camera of `estimate`: its rotation when it has one without a position ("rotation only"),
  // drawn as a direction from the true centre; nullopt otherwise.
  std::vector<std::optional<Eigen::Quaterniond>> rotation_only;
  std::optional<Rig> truth;  // the same cameras, in the same order, with their true cam_from_rig
  bool metric = false;       // the estimate is in metres
};

// The SVG text. Circles carry class "estimate" or "truth" and a data-camera attribute with the
// camera's name (the tests read them back). Throws std::invalid_argument when the truth's cameras
// differ from the estimate's, or when the first camera has no pose.
std::string RigTopDownSvg(const RigPlotInput& input);

}  // namespace rigsim
