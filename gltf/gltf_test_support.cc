#include "gltf/gltf_test_support.h"

#include <stdexcept>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "testing/expect_error.h"

namespace rigsim::gltf_test {

std::vector<Eigen::Vector3f> TriangleCorners(const SceneMesh& m) {
  std::vector<Eigen::Vector3f> out;
  for (uint32_t i : m.indices) out.push_back(m.positions[i]);
  return out;
}

Eigen::Vector3f FaceNormal(const SceneMesh& m, size_t tri) {
  const Eigen::Vector3f a = m.positions[m.indices[3 * tri]], b = m.positions[m.indices[3 * tri + 1]], c = m.positions[m.indices[3 * tri + 2]];
  return (b - a).cross(c - a).normalized();
}

bool HasWarning(const Scene& s, const std::string& part) {
  for (const std::string& w : s.warnings) {
    if (w.find(part) != std::string::npos) return true;
  }
  return false;
}

void ExpectLoadFails(const std::filesystem::path& path, const GltfLoadOptions& options, const std::string& part,
                     const char* file, int line) {
  const ::testing::ScopedTrace trace(file, line, "ExpectLoadFails");
  EXPECT_THAT([&] { LoadGltf(path, options); }, ThrowsNaming<std::runtime_error>(path, part));
}

void ExpectLoadFails(const std::filesystem::path& path, const std::string& part, const char* file, int line) {
  ExpectLoadFails(path, GltfLoadOptions{}, part, file, line);
}

}  // namespace rigsim::gltf_test
