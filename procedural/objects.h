// Geometry builders shared by the procedural scene generators: textured quads, boxes, cylinders,
// noisy blobs and node placements, written into gltf/scene_builder.h MeshData.
//
// Conventions: glTF world (+Y up, metres). Quads are given by their top-left corner and the full
// right and down edges as seen from the front; the front normal is right x up and triangles are
// counter-clockwise seen from it. UvRect selects the part of a texture atlas a face shows.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "gltf/scene_builder.h"

namespace rigsim::procedural {

using Eigen::Vector2f;
using Eigen::Vector3f;

struct UvRect {
  float u0 = 0, v0 = 0, u1 = 1, v1 = 1;
};

void AddQuad(MeshData& m, const Vector3f& tl, const Vector3f& right, const Vector3f& down, const UvRect& uv = {});

// Axis-aligned box; every face shows `uv` of the texture.
void AddBox(MeshData& m, const Vector3f& lo, const Vector3f& hi, const UvRect& uv = {});

// Vertical cylinder (with a top cap) standing on `base`.
void AddCylinder(MeshData& m, const Vector3f& base, float radius, float height, int segments, const UvRect& uv = {});

// Sphere-like blob with radial noise (tree crowns, heads).
void AddBlob(MeshData& m, const Vector3f& centre, const Vector3f& radii, float bumpiness, uint64_t seed, const UvRect& uv = {});

Eigen::Matrix4d Placement(float x, float z, float yaw);

// A car body on the car atlas (procedural/textures.h PaintCarAtlas): body box, cabin, four wheels.
// Origin on the ground at the car's centre, length along +z.
MeshData CarMesh(float length, float width, float cabin_height);
// A bus: a long box whose two sides show the whole poster texture (material 1 of the node) and
// whose ends and roof show the body paint (material 0). Parts: {body, poster sides}.
std::vector<MeshPart> BusParts(float length, float width, float height, int body_material, int poster_material);
// A standing person on the person atlas; origin between the feet.
MeshData PersonMesh(float scale, uint64_t seed);
// `count` vertical quads crossing at `centre` (rotated evenly), each `size` x `size`, showing the
// whole texture: alpha-masked foliage cards.
void AddCrossedCards(MeshData& m, const Vector3f& centre, float size, int count, float start_angle);

}  // namespace rigsim::procedural
