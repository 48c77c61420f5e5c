// Glass in the facades' windows and puddles on the road: the glossy surfaces of a street that
// mirror the world in the renderer's one specular bounce (renderer/specular_bounce.h), as shop
// windows and wet asphalt do in real photos.
//
// Both are extra primitives of the node they belong to, so they keep its class and instance: a
// window's glass is part of its building (Cityscapes has no window class; its annotations count
// windows as building), a puddle part of its road segment (Cityscapes labels wet road as road).
// glTF's metallic-roughness model has no transmission without an extension; glass and water are
// dielectrics (metallic 0, reflectance 4 % head on, rising to all at grazing angles by Schlick's
// Fresnel) with a near-zero roughness, over what shows through them: the painted pane behind the
// glass, the asphalt under the water, darkened.
//
// World: glTF (+Y up, metres). Deterministic: the same Rng state gives the same geometry.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "gltf/scene_builder.h"
#include "procedural/textures.h"

namespace rigsim::procedural {

// Window glass: smooth enough for a sharp mirror image; its base colour is the painted pane
// scaled by kWindowGlassShade (a coated pane lets less of the room behind it through).
inline constexpr float kWindowGlassRoughness = 0.03f;
inline constexpr float kWindowGlassShade = 0.6f;
// The glass stands this far in front of the facade plane (in front of the painted frame).
inline constexpr float kWindowGlassOffsetM = 0.01f;
// Still water: a mirror; the asphalt under it is darker than dry asphalt (water fills the pores).
inline constexpr float kPuddleRoughness = 0.02f;
inline constexpr float kPuddleShade = 0.45f;
// A puddle's surface stands this far above its ground.
inline constexpr float kPuddleHeightM = 0.004f;

// A glass material over `texture` (the facade's): kWindowGlassShade of its colour, kWindowGlassRoughness.
int GlassMaterial(SceneBuilder& builder, const std::string& name, int texture);
// A puddle material over `texture` (the ground's): kPuddleShade of its colour, kPuddleRoughness.
int PuddleMaterial(SceneBuilder& builder, const std::string& name, int texture);

// The glass of `panes` (canvas pixels of a w x h texture) on the facade quad given as objects.h's
// AddQuad takes it (top-left corner, full right and down edges, front normal right x up), moved
// kWindowGlassOffsetM along the front normal; each pane shows its own part of the facade's texture.
MeshData GlassPanes(const Eigen::Vector3f& top_left, const Eigen::Vector3f& right, const Eigen::Vector3f& down, int w, int h,
                    const std::vector<Pane>& panes);

// Puddles on the horizontal ground rectangle [x0, x1] x [z0, z1] at height y (+Y up), covering
// about `wet` of its area (0 = none; they never overlap and stay 0.2 m inside it): irregular
// ellipses, longer along z than across, kPuddleHeightM above the ground. Texture coordinates are
// the rectangle's (u = 0 at x0, 1 at x1; v = 0 at z0, 1 at z1), so a puddle shows the ground's own
// texture beneath it.
MeshData Puddles(Rng& rng, float x0, float z0, float x1, float z1, float y, float wet);

// The area of a mesh's triangles projected on the ground plane (m^2).
float GroundArea(const MeshData& mesh);

}  // namespace rigsim::procedural
