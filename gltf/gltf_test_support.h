// What the glTF loader's tests share beyond the test toolkit (testing/): looks at what LoadGltf
// returns, and the check that it refuses a file naming it.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "gltf/gltf_loader.h"
#include "scene/scene.h"
#include "testing/gltf_builder.h"
#include "testing/temp_dir.h"

namespace rigsim::gltf_test {

using json = nlohmann::json;

std::vector<Eigen::Vector3f> TriangleCorners(const SceneMesh& m);
Eigen::Vector3f FaceNormal(const SceneMesh& m, size_t tri);
bool HasWarning(const Scene& s, const std::string& part);

// Expects LoadGltf(path, options) to throw a std::runtime_error whose message starts with the
// file's name and contains `part`; a failure names the calling line (the builtins, not
// std::source_location, which Debian 12's clang does not provide).
void ExpectLoadFails(const std::filesystem::path& path, const GltfLoadOptions& options, const std::string& part,
                     const char* file = __builtin_FILE(), int line = __builtin_LINE());
void ExpectLoadFails(const std::filesystem::path& path, const std::string& part, const char* file = __builtin_FILE(),
                     int line = __builtin_LINE());

}  // namespace rigsim::gltf_test
