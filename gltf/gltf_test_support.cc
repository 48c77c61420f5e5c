#include "gltf/gltf_test_support.h"

#include <fstream>
#include <stdexcept>

#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "tests/data_uri.h"

namespace rigsim::gltf_test {

std::filesystem::path TempDir() {
  const auto* info = testing::UnitTest::GetInstance()->current_test_info();
  const auto dir = std::filesystem::temp_directory_path() / "rigsim_gltf_loader_test" / info->name();
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

std::string TinyPngUri() {
  cv::Mat bgr(2, 2, CV_8UC3, cv::Scalar(10, 20, 30));
  std::vector<uint8_t> png;
  cv::imencode(".png", bgr, png);
  return DataUri("image/png", png);
}

TestGltf::TwoSets TestGltf::QuadWithTwoTexcoordSets() {
  return {Positions(kQuad), Accessor<float>({0, 0, 1, 0, 1, 1, 0, 1}, kFloat, "VEC2", 4),
          Accessor<float>({0.25f, 0.25f, 0.75f, 0.25f, 0.75f, 0.75f, 0.25f, 0.75f}, kFloat, "VEC2", 4)};
}

void TestGltf::TinyTexture() {
  doc["images"] = json::array({{{"uri", TinyPngUri()}}});
  doc["textures"] = json::array({{{"source", 0}}});
}

std::filesystem::path TestGltf::Write(const std::filesystem::path& dir, const std::string& name, bool data_uri) {
  json d = doc;
  if (data_uri) {
    d["buffers"] = json::array({{{"byteLength", bin.size()}, {"uri", DataUri("application/octet-stream", bin)}}});
  } else {
    std::ofstream(dir / (name + ".bin"), std::ios::binary).write(reinterpret_cast<const char*>(bin.data()), std::streamsize(bin.size()));
    d["buffers"] = json::array({{{"byteLength", bin.size()}, {"uri", name + ".bin"}}});
  }
  for (const json& b : extra_buffers) d["buffers"].push_back(b);
  const auto path = dir / (name + ".gltf");
  std::ofstream(path) << d.dump(1);
  return path;
}

std::filesystem::path TestGltf::WriteGlb(const std::filesystem::path& dir, const std::string& name) {
  json d = doc;
  d["buffers"] = json::array({{{"byteLength", bin.size()}}});
  for (const json& b : extra_buffers) d["buffers"].push_back(b);
  std::string text = d.dump();
  while (text.size() % 4) text += ' ';
  std::vector<uint8_t> chunk = bin;
  while (chunk.size() % 4) chunk.push_back(0);
  std::vector<uint32_t> header = {0x46546C67u, 2, uint32_t(28 + text.size() + chunk.size()), uint32_t(text.size()), 0x4E4F534Au};
  const std::vector<uint32_t> bin_header = {uint32_t(chunk.size()), 0x004E4942u};
  const auto path = dir / (name + ".glb");
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(header.data()), 20);
  out.write(text.data(), std::streamsize(text.size()));
  out.write(reinterpret_cast<const char*>(bin_header.data()), 8);
  out.write(reinterpret_cast<const char*>(chunk.data()), std::streamsize(chunk.size()));
  return path;
}

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

void ExpectThrowsWithOptions(const std::filesystem::path& path, const GltfLoadOptions& options, const std::string& part) {
  try {
    LoadGltf(path, options);
    ADD_FAILURE() << "no exception for " << path;
  } catch (const std::runtime_error& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.rfind(path.string(), 0), 0u) << msg;
    EXPECT_NE(msg.find(part), std::string::npos) << msg;
  }
}

void ExpectThrowsWith(const std::filesystem::path& path, const std::string& part) {
  ExpectThrowsWithOptions(path, GltfLoadOptions{}, part);
}

}  // namespace rigsim::gltf_test
