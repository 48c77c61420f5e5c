// Fuzzes the glTF loader (gltf/gltf_loader.h) with arbitrary .gltf / .glb bytes.
//
// LoadGltf reads from a path, so each input is written to a file in a private, empty folder:
// relative buffer and image URIs in the input then resolve to nothing, as for a lone file.
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include "gltf/gltf_loader.h"

namespace {

// Leaked on purpose: the exit handler that removes the folder runs after static destructors.
const std::filesystem::path& InputPath() {
  static const std::filesystem::path* path = [] {
    const auto dir = std::filesystem::temp_directory_path() / ("rigsim_fuzz_gltf_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    std::atexit([] {
      std::error_code ec;
      std::filesystem::remove_all(InputPath().parent_path(), ec);
    });
    return new std::filesystem::path(dir / "input.gltf");
  }();
  return *path;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  {
    std::ofstream out(InputPath(), std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
  }
  rigsim::GltfLoadOptions options;
  options.max_accessor_count = size_t(1) << 20;  // keeps each run fast; the checks are the same
  options.max_image_pixels = uint64_t(1) << 22;
  try {
    const rigsim::Scene scene = rigsim::LoadGltf(InputPath(), options);
    // What the loader returns must be consistent: every index addresses a vertex.
    for (const rigsim::SceneMesh& m : scene.meshes) {
      if (m.indices.size() % 3 != 0) __builtin_trap();
      for (uint32_t i : m.indices) {
        if (i >= m.positions.size()) __builtin_trap();
      }
      if (!m.normals.empty() && m.normals.size() != m.positions.size()) __builtin_trap();
      if (!m.texcoords.empty() && m.texcoords.size() != m.positions.size()) __builtin_trap();
      if (m.material >= int(scene.materials.size())) __builtin_trap();
    }
    for (const rigsim::Material& mat : scene.materials) {
      if (mat.base_color_texture >= int(scene.textures.size())) __builtin_trap();
    }
    for (const rigsim::Texture& t : scene.textures) {
      if (t.rgba.size() != size_t(t.width) * size_t(t.height) * 4) __builtin_trap();
    }
  } catch (const std::runtime_error&) {
    // rejected with a message: fine
  }
  return 0;
}
