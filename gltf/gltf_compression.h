// The glTF extensions that compress meshes, for the loader (internal to gltf/: it
// includes tinygltf): KHR_draco_mesh_compression (libdraco) and EXT_meshopt_compression
// (meshoptimizer). tinygltf reads neither and refuses what they leave out (a Draco primitive's
// index accessor has no buffer view; meshopt's fallback buffer has no data). So the loader loads
// such a file in two steps: tinygltf reads a version whose JSON it accepts
// (MakeCompressedMeshesReadable, part of gltf/readable_gltf.h), then DecodeMeshoptBufferViews
// fills the fallback buffers and DecodeDracoPrimitives replaces each Draco primitive's indices and
// attributes with plain accessors, which the rest of the loader reads like any other.
#pragma once

#include <cstddef>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

namespace rigsim {

inline constexpr std::string_view kDracoExtension = "KHR_draco_mesh_compression";
inline constexpr std::string_view kMeshoptExtension = "EXT_meshopt_compression";

// How the loader's messages name a primitive: "mesh 3 'wheel' primitive 0".
std::string PrimitiveLabel(size_t mesh, const std::string& mesh_name, size_t prim);

// Rewrites a glTF document so that tinygltf reads it: the index accessor of every Draco primitive
// that has no buffer view points at the primitive's Draco buffer view (a placeholder:
// DecodeDracoPrimitives points it at the decoded indices), and every meshopt fallback buffer
// without data is one zero byte, its byteLength kept in *fallback_lengths. Returns whether it
// changed anything. Throws std::invalid_argument naming the primitive or buffer when an extension
// object cannot be made readable.
bool MakeCompressedMeshesReadable(nlohmann::json& doc, std::map<int, size_t>* fallback_lengths);

// Gives each fallback buffer its length back (at most `max_bytes` in all) and decodes into it
// every buffer view compressed with EXT_meshopt_compression (attributes, triangles or indices,
// with their filters). Views over buffers that hold their data are left as they are. Throws
// std::invalid_argument naming the buffer view when its extension object or data is malformed.
// Returns how many views it decoded.
size_t DecodeMeshoptBufferViews(tinygltf::Model& model, const std::map<int, size_t>& fallback_lengths, size_t max_bytes);

// Decodes every primitive that carries KHR_draco_mesh_compression: its indices and the attributes
// the extension names become new accessors (over new buffers and buffer views appended to the
// model) that the primitive points to; the extension object is then removed. At most
// `max_elements` vertices or indices per primitive. Throws std::invalid_argument naming the mesh
// and primitive when the extension object or its data is malformed. Returns how many primitives
// it decoded.
size_t DecodeDracoPrimitives(tinygltf::Model& model, size_t max_elements);

}  // namespace rigsim
