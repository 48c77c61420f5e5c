// The rig's own vehicle (make-rig --ego-vehicle): a low-poly car body around a rig, sized from
// where its cameras are, labelled `ego vehicle` (Cityscapes 1), with glossy paint and glass that the
// renderer's specular bounce lets reflect the world.
//
// Shape (rig frame: x right, y down, z forward): a roof kRoofGap below the lowest camera, reaching
// kRoofMargin beyond the outermost cameras to the sides and kRoofEndMargin to the front and rear
// (at least 1.3 m wide and 1.8 m long), so that every camera sits on the roof and sees its edge in
// the lower part of its view. Where that least size puts the edge further from a camera looking
// out (more out than up or down), in the direction it looks, than kRoofMargin (cameras grouped
// closer than a car's roof, as on a roof rack), the roof is lower, so that the camera sees the edge
// no higher than one at the roof's side edge does (kRoofGap down over kRoofMargin out). A
// windshield (0.8 m long) and rear window (0.6 m) slope down to the beltline 0.4 m below the roof;
// below it a body 0.12 m wider on each side, with a 1.1 m bonnet (hood) in front of the windshield
// and a 0.5 m boot behind the rear window, down to 0.2 m above the ground. No camera is inside; a
// camera whose central ray meets the body within kMinClearance of its lens is refused.
//
// The file holds the body in the rig frame turned to glTF's axes (+Y up, +Z forward, hence
// x_gltf = -x_rig, y_gltf = -y_rig, z_gltf = z_rig), so a glTF viewer shows it upright.
#pragma once

#include <cstdint>
#include <vector>

#include "geometry/rig.h"
#include "gltf/scene_builder.h"
#include "scene/scene.h"

namespace rigsim {

inline constexpr char kEgoVehicleFile[] = "ego_vehicle.glb";  // beside rig.json
inline constexpr double kRoofMargin = 0.1;      // m the roof reaches beyond the outermost cameras sideways
inline constexpr double kRoofEndMargin = 0.05;  // m it reaches beyond the front-most and rear-most
inline constexpr double kRoofGap = 0.05;        // m the roof lies below the lowest camera, at least
inline constexpr double kMinClearance = 0.1;  // m a camera's central ray runs before it may meet the body

// The body's two parts in the rig frame: painted panels and glass.
struct EgoVehicleMeshes {
  MeshData paint, glass;
};

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
