// The rig's own vehicle (make-rig --ego-vehicle): a low-poly car body around a rig, sized from
// where its cameras are, labelled `ego vehicle` (Cityscapes 1), with glossy paint and glass that the
// renderer's specular bounce lets reflect the world.
//
// Shape (the car's frame: x right, y down, z forward): every camera sits on the car's skin, as
// cameras of a car rig sit on or just above its roof, mirrors and bumpers. The roof lies kRoofGap
// below the lowest camera and reaches kRoofMargin beyond the outermost cameras every way, no
// further: each camera stands at the roof's edge it looks out over and sees that edge just below
// it (a camera looking straight out at an edge, level, 27 degrees below its horizon; one looking
// out over a corner, less), and beyond it the windshield, bonnet or side falling away, in the
// bottom of its view, as a real car's cameras see their car. A windshield (0.8 m long) and rear
// window (0.6 m) slope down to the beltline 0.4 m below the roof; below it a body 0.12 m wider on
// each side (kMinBodyWidth wide at least), with a 1.1 m bonnet (hood) in front of the windshield
// and a 0.5 m boot behind the rear window, down to 0.2 m above the ground. A body shorter than
// kMinBodyLength gets a longer boot, or bonnet, at the end no camera looks out over (half each when
// cameras look out over both or neither). The car's frame is the rig frame levelled to the plane
// through the cameras' centres when they all lie within kRoofGap of it and it tilts by
// kMaxLevelTilt at most (a rig frame is its first camera's, often a degree or two off the car's
// level), else the rig frame. No camera is inside; a camera whose central ray meets the body within
// kMinClearance of its lens is refused.
//
// The file holds the body in the rig frame turned to glTF's axes (+Y up, +Z forward, hence
// x_gltf = -x_rig, y_gltf = -y_rig, z_gltf = z_rig), so a glTF viewer shows it upright.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "geometry/rig.h"
#include "gltf/scene_builder.h"
#include "scene/scene.h"

namespace rigsim {

inline constexpr char kEgoVehicleFile[] = "ego_vehicle.glb";  // beside rig.json
inline constexpr double kRoofMargin = 0.1;  // m the roof reaches beyond the outermost cameras, every way
inline constexpr double kRoofGap = 0.05;        // m the roof lies below the lowest camera
inline constexpr double kMinBodyWidth = 1.6;   // m the body below the beltline is wide, at least
inline constexpr double kMinBodyLength = 4.2;  // m it is long, at least
inline constexpr double kMaxLevelTilt = 0.0873;  // rad (5 degrees) the car may be tilted to the rig frame
inline constexpr double kMinClearance = 0.1;  // m a camera's central ray runs before it may meet the body

// The body's two parts in the rig frame: painted panels and glass.
struct EgoVehicleMeshes {
  MeshData paint, glass;
};

// The car's frame in the rig frame (rig_from_car): level with the plane through the cameras'
// centres when the cameras lie within kRoofGap of it and it tilts less than kMaxLevelTilt, as the
// cameras of a roof rack or a car's body do (the rig frame is its first camera's, which may sit a
// degree or two off the car's level: over a 1.4 m rig that moves a camera 5 cm, the roof's gap);
// else the rig frame itself. The plane's slopes are ridge-regularised so that cameras in a line
// (along x, as three front cameras) give it no slope across the line.
// `centres` are the cameras' centres in the rig frame. The columns of the result are the car's
// right, down and forward in the rig frame (a rotation: det +1).
Eigen::Matrix3d RigFromCar(const std::vector<Eigen::Vector3d>& centres);

// The body of `rig` (every camera needs cam_from_rig), its rig origin `ground_below_rig_m` above the
// ground. Throws std::invalid_argument naming the camera when one looks into the body, and when a
// camera has no pose (without the option's name: make-rig and the sweep name theirs).
EgoVehicleMeshes EgoVehicleInRig(const Rig& rig, double ground_below_rig_m);

// The body as a binary glTF (glTF axes, above), one node `ego vehicle` of class `ego vehicle`.
std::vector<uint8_t> EgoVehicleGlb(const Rig& rig, double ground_below_rig_m);

// A loaded ego-vehicle file turned back from glTF's axes into the rig frame, as the renderer
// attaches it (Renderer::SetAttached).
void EgoVehicleToRigFrame(Scene& scene);

}  // namespace rigsim
