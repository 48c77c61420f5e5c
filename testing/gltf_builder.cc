#include "testing/gltf_builder.h"

#include <cmath>
#include <fstream>
#include <numbers>
#include <stdexcept>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "common/base64.h"

namespace rigsim {
namespace {

using json = nlohmann::json;

void WriteBytes(const std::filesystem::path& path, const void* data, size_t size) {
  std::ofstream out(path, std::ios::binary);
  out.write(static_cast<const char*>(data), std::streamsize(size));
  if (!out) throw std::runtime_error(path.string() + ": cannot write");
}

int ComponentsOf(const std::string& type) {
  if (type == "SCALAR") return 1;
  if (type == "VEC2") return 2;
  if (type == "VEC3") return 3;
  if (type == "VEC4" || type == "MAT2") return 4;
  if (type == "MAT3") return 9;
  if (type == "MAT4") return 16;
  throw std::invalid_argument("GltfBuilder: unknown accessor type '" + type + "'");
}

}  // namespace

std::string DataUri(std::string_view mime_type, const std::vector<uint8_t>& data) {
  return "data:" + std::string(mime_type) + ";base64," +
         Base64Encode(std::string_view(reinterpret_cast<const char*>(data.data()), data.size()));
}

std::string TinyPngUri() {
  cv::Mat bgr(2, 2, CV_8UC3, cv::Scalar(10, 20, 30));
  std::vector<uint8_t> png;
  cv::imencode(".png", bgr, png);
  return DataUri("image/png", png);
}

json GltfCamerasDocument() {
  const double h = std::sqrt(0.5);
  auto perspective = [](double aspect) {
    json p = {{"yfov", std::numbers::pi / 3}, {"znear", 0.1}};
    if (aspect > 0) p["aspectRatio"] = aspect;
    return json{{"type", "perspective"}, {"perspective", p}};
  };
  const json orthographic = {{"type", "orthographic"},
                             {"name", "plan"},
                             {"orthographic", {{"xmag", 1}, {"ymag", 1}, {"znear", 0.1}, {"zfar", 100}}}};
  return {{"asset", {{"version", "2.0"}}},
          {"cameras", {perspective(0.0), perspective(2.0), orthographic}},
          {"nodes",
           {{{"name", "front"}, {"camera", 0}, {"translation", {1, 2, 3}}, {"rotation", {0, h, 0, h}}},
            {{"name", "mount"}, {"translation", {0, 0, -10}}, {"rotation", {0, 1, 0, 0}}, {"scale", {2, 2, 2}}, {"children", {2}}},
            {{"name", "back"}, {"camera", 1}, {"translation", {2, 0, 0}}},
            {{"name", "top"}, {"camera", 2}, {"translation", {0, 50, 0}}}}},
          {"scenes", {{{"nodes", {1, 0, 3}}}}},
          {"scene", 0}};
}

size_t GltfBuilder::AppendToBin(const void* data, size_t bytes) {
  while (bin.size() % 4) bin.push_back(0);
  const size_t offset = bin.size();
  bin.resize(offset + bytes);
  if (bytes > 0) std::memcpy(bin.data() + offset, data, bytes);
  return offset;
}

int GltfBuilder::Floats(const std::vector<float>& values, const std::string& type) {
  return Accessor(values, kGltfFloat, type, values.size() / ComponentsOf(type));
}

GltfBuilder::TwoSets GltfBuilder::QuadWithTwoTexcoordSets() {
  return {Positions(kUnitQuad), Floats({0, 0, 1, 0, 1, 1, 0, 1}, "VEC2"),
          Floats({0.25f, 0.25f, 0.75f, 0.25f, 0.75f, 0.75f, 0.25f, 0.75f}, "VEC2")};
}

void GltfBuilder::TinyTexture() {
  doc["images"] = json::array({{{"uri", TinyPngUri()}}});
  doc["textures"] = json::array({{{"source", 0}}});
}

int GltfBuilder::Mesh(json attributes, int indices, int mode, int material, json extras) {
  json prim = {{"attributes", attributes}, {"mode", mode}};
  if (indices >= 0) prim["indices"] = indices;
  if (material >= 0) prim["material"] = material;
  json mesh = {{"primitives", json::array({prim})}};
  if (!extras.is_null()) mesh["extras"] = extras;
  doc["meshes"].push_back(mesh);
  return int(doc["meshes"].size()) - 1;
}

int GltfBuilder::Node(json node) {
  doc["nodes"].push_back(node);
  return int(doc["nodes"].size()) - 1;
}

void GltfBuilder::Scene(std::vector<int> roots) {
  doc["scene"] = 0;
  doc["scenes"] = json::array({{{"nodes", roots}}});
}

void GltfBuilder::AddRoot(int node) {
  if (!doc.contains("scenes")) Scene({});
  doc["scenes"][0]["nodes"].push_back(node);
}

int GltfBuilder::Triangle(const std::vector<float>& xyz, const std::string& cls) {
  const int node = Node({{"mesh", Mesh({{"POSITION", Positions(xyz)}})}, {"extras", {{"class", cls}}}});
  AddRoot(node);
  return node;
}

int GltfBuilder::Quad(const std::array<Eigen::Vector3d, 4>& c, const std::string& cls, int material,
                      const std::vector<Eigen::Vector4f>& rgba) {
  const int order[6] = {0, 1, 2, 0, 2, 3};
  const float uv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  std::vector<float> xyz, st, colours;
  for (int i : order) {
    for (int k = 0; k < 3; ++k) xyz.push_back(float(c[i][k]));
    st.push_back(uv[i][0]);
    st.push_back(uv[i][1]);
    for (int k = 0; k < 4 && !rgba.empty(); ++k) colours.push_back(rgba[i][k]);
  }
  json attributes = {{"POSITION", Positions(xyz)}};
  if (material >= 0) attributes["TEXCOORD_0"] = Floats(st, "VEC2");
  if (!rgba.empty()) attributes["COLOR_0"] = Floats(colours, "VEC4");
  const int node = Node({{"mesh", Mesh(attributes, -1, 4, material)}, {"extras", {{"class", cls}}}});
  AddRoot(node);
  return node;
}

int GltfBuilder::Square(const Eigen::Vector3d& centre, const Eigen::Vector3d& right, const Eigen::Vector3d& up,
                        double size, const std::string& cls, int material) {
  const double h = 0.5 * size;
  return Quad({centre - h * right + h * up, centre + h * right + h * up, centre + h * right - h * up,
               centre - h * right - h * up},
              cls, material);
}

json GltfBuilder::Document(const std::string& bin_uri) const {
  json d = doc;
  if (d.contains("buffers")) return d;
  json buffer0 = {{"byteLength", bin.size()}};
  buffer0["uri"] = bin_uri.empty() ? DataUri("application/octet-stream", bin) : bin_uri;
  d["buffers"] = json::array({buffer0});
  for (const json& b : extra_buffers) d["buffers"].push_back(b);
  return d;
}

std::filesystem::path GltfBuilder::Write(const std::filesystem::path& dir, const std::string& name) const {
  WriteBytes(dir / (name + ".bin"), bin.data(), bin.size());
  const auto path = dir / (name + ".gltf");
  const std::string text = Document(name + ".bin").dump(1);
  WriteBytes(path, text.data(), text.size());
  return path;
}

std::filesystem::path GltfBuilder::WriteEmbedded(const std::filesystem::path& dir, const std::string& name) const {
  const auto path = dir / (name + ".gltf");
  const std::string text = Document().dump(1);
  WriteBytes(path, text.data(), text.size());
  return path;
}

std::filesystem::path GltfBuilder::WriteGlb(const std::filesystem::path& dir, const std::string& name) const {
  json d = doc;
  if (!d.contains("buffers")) {
    d["buffers"] = json::array({{{"byteLength", bin.size()}}});
    for (const json& b : extra_buffers) d["buffers"].push_back(b);
  }
  std::string text = d.dump();
  while (text.size() % 4) text += ' ';
  std::vector<uint8_t> chunk = bin;
  while (chunk.size() % 4) chunk.push_back(0);
  // The 12-byte header (magic "glTF", version 2, total length), then each chunk's length and type.
  const std::vector<uint32_t> header = {0x46546C67u, 2, uint32_t(28 + text.size() + chunk.size()), uint32_t(text.size()),
                                        0x4E4F534Au};
  const std::vector<uint32_t> bin_header = {uint32_t(chunk.size()), 0x004E4942u};
  std::string bytes(reinterpret_cast<const char*>(header.data()), 20);
  bytes += text;
  bytes.append(reinterpret_cast<const char*>(bin_header.data()), 8);
  bytes.append(reinterpret_cast<const char*>(chunk.data()), chunk.size());
  const auto path = dir / (name + ".glb");
  WriteBytes(path, bytes.data(), bytes.size());
  return path;
}

}  // namespace rigsim
