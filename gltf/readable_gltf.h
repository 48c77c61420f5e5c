// Valid glTF 2.0 that tinygltf 2.7 refuses, made readable (internal to gltf/). The loader hands
// tinygltf a rewritten copy of the file's JSON and undoes the rewrite on the model it gets back:
//  - a buffer without `uri` (allowed in a .gltf when nothing reads it, and in a .glb for all but
//    the first buffer): tinygltf looks for a file with an empty name. It gets one zero byte; the
//    loader empties it again, and refuses it only when an accessor reads it.
//  - an accessor without `bufferView` that a primitive uses as indices (its values are zeros,
//    which sparse values may replace): tinygltf refuses it. It points at a placeholder view for
//    tinygltf; the loader reads it as zeros plus its sparse values, as any accessor without one.
//  - a data URI tinygltf does not decode: percent-encoded instead of base64
//    (`data:application/gltf-buffer,...`), or of a media type it does not know (`image/webp`).
//    Decoded here, and handed to tinygltf as base64 `application/octet-stream`.
//  - an accessor of a type or componentType glTF does not define (allowed when nothing reads it):
//    tinygltf refuses the file. It is given SCALAR floats; the loader refuses it only when read.
//  - compressed meshes (gltf/gltf_compression.h).
// A buffer or image whose uri is a web address (http:, https:, ...) is refused here, naming it:
// rigsim reads the file and the files beside it, nothing remote.
#pragma once

#include <cstddef>
#include <map>
#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace rigsim {

// The JSON of a .gltf file (all of it) or of a .glb file (its first chunk; empty when the
// header is malformed or the chunk runs past the end).
std::string_view GltfJson(const std::vector<unsigned char>& file);

struct ReadableGltf {
  // What tinygltf reads: the file with its JSON rewritten; empty when nothing needed rewriting
  // (or the JSON cannot be read: tinygltf then says what is wrong).
  std::vector<unsigned char> bytes;
  std::map<int, size_t> fallback_lengths;       // meshopt fallback buffer -> its byteLength in the file
  std::set<int> dataless_buffers;               // buffers without uri and data: empty for the loader
  std::set<int> viewless_accessors;             // index accessors without bufferView: bufferView -1 again
  std::map<int, std::string> unknown_types;     // accessor -> its type as the file writes it
  std::map<int, int> unknown_component_types;   // accessor -> its componentType as the file writes it
};

// Throws std::invalid_argument naming the buffer, image, primitive or buffer view that cannot be
// made readable (a remote uri, a malformed data URI or compression extension).
ReadableGltf ReadableGltfOf(const std::vector<unsigned char>& file);

}  // namespace rigsim
