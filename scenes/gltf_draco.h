// KHR_draco_mesh_compression for the glTF loader (internal to the scenes module: it includes
// tinygltf). Debian's tinygltf is built without Draco and refuses a compressed primitive's index
// accessor, which has no buffer view, before anything could decode it. So the loader loads such a
// file in two steps: tinygltf reads a copy whose JSON it accepts (DracoReadableCopy), then
// DecodeDracoPrimitives replaces each compressed primitive's indices and attributes with plain
// accessors over the decoded data, which the rest of the loader reads like any other. (The copy
// is a file because Debian's tinygltf library and header disagree on the TinyGLTF object's
// layout: its loaders from memory find no file callbacks for external buffers.)
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <tiny_gltf.h>

namespace rigsim {

inline constexpr std::string_view kDracoExtension = "KHR_draco_mesh_compression";

// How the loader's messages name a primitive: "mesh 3 'wheel' primitive 0".
std::string PrimitiveLabel(size_t mesh, const std::string& mesh_name, size_t prim);

// When the .gltf or .glb file names the extension: the bytes of a copy tinygltf accepts, to be
// written to the folder `copy_dir()` makes (called only then). In its JSON, the index accessor of
// every compressed primitive that has no buffer view points at the primitive's Draco buffer view
// (a placeholder: DecodeDracoPrimitives points it at the decoded indices), and relative buffer and
// image URIs lead back to `file`'s folder. Otherwise (or when the JSON is not readable: tinygltf
// then says what is wrong), nothing. Throws std::invalid_argument naming the primitive when its
// extension object does not name a buffer view of the file.
struct DracoCopy {
  std::vector<unsigned char> bytes;
  std::string uri_prefix;  // what leads the copy's URIs back to the original's folder
};
std::optional<DracoCopy> DracoReadableCopy(const std::filesystem::path& file,
                                           const std::function<std::filesystem::path()>& copy_dir);

// Decodes every primitive that carries the extension: its indices and the attributes the
// extension names become new accessors (over new buffers and buffer views appended to the model)
// that the primitive points to; the extension object is then removed. At most `max_elements`
// vertices or indices per primitive. Throws std::invalid_argument naming the mesh and primitive
// when the extension object or its data is malformed.
void DecodeDracoPrimitives(tinygltf::Model& model, size_t max_elements);

}  // namespace rigsim
