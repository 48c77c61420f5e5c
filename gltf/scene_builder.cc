#include "gltf/scene_builder.h"

#include <cmath>
#include <cstring>
#include <fstream>
#include <stdexcept>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>
#include "dataset/image_codecs.h"
#include "labels/cityscapes.h"

namespace rigsim {
namespace {

using nlohmann::json;

constexpr int kFloat = 5126;
constexpr int kUnsignedShort = 5123;
constexpr int kUnsignedInt = 5125;
constexpr int kArrayBuffer = 34962;
constexpr int kElementArrayBuffer = 34963;

// Appends raw bytes to the binary chunk, 4-byte aligned so every accessor is aligned, and
// registers them as a bufferView. Returns the bufferView index.
int AddView(std::vector<uint8_t>* bin, json* views, const void* data, size_t size, int target) {
  while (bin->size() % 4 != 0) bin->push_back(0);
  const size_t offset = bin->size();
  bin->resize(offset + size);
  if (size > 0) std::memcpy(bin->data() + offset, data, size);
  json v = {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", size}};
  if (target != 0) v["target"] = target;
  views->push_back(v);
  return int(views->size()) - 1;
}

std::vector<uint8_t> EncodeImage(const std::string& name, int width, int height, int channels,
                                 const std::vector<uint8_t>& pixels, int quality, std::string* mime) {
  bool opaque = true;
  if (channels == 4) {
    for (size_t i = 3; i < pixels.size() && opaque; i += 4) opaque = pixels[i] == 255;
  }
  if (opaque) {
    // Quality as asked, optimised Huffman tables, as OpenCV's encoder wrote them before.
    std::vector<uint8_t> rgb = pixels;
    if (channels == 4) {
      rgb.resize(size_t(width) * height * 3);
      for (size_t i = 0; i < rgb.size() / 3; ++i) std::memcpy(&rgb[i * 3], &pixels[i * 4], 3);
    }
    *mime = "image/jpeg";
    return EncodeJpeg(rgb.data(), width, height, 3, {quality, true, false}, "texture '" + name + "'");
  }
  // OpenCV's PNG defaults, which wrote the shipped scenes: zlib's fastest level, run-length
  // strategy (Z_RLE), the Sub filter on every row.
  *mime = "image/png";
  return EncodePng(pixels.data(), width, height, 4, 8, {1, 3, 0x10 /* PNG_FILTER_SUB */, false}, "texture '" + name + "'");
}

// One primitive of a node's mesh: its vertex attributes and its indices (16-bit when they fit) as
// accessors over new buffer views.
json PrimitiveJson(const MeshPart& part, std::vector<uint8_t>* bin, json* views, json* accessors) {
  const MeshData& m = part.mesh;
  Eigen::Vector3f lo = m.positions[0], hi = m.positions[0];
  for (const Eigen::Vector3f& p : m.positions) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  json attributes;
  const size_t n = m.positions.size();
  int view = AddView(bin, views, m.positions.data(), n * sizeof(Eigen::Vector3f), kArrayBuffer);
  accessors->push_back({{"bufferView", view}, {"componentType", kFloat}, {"count", n}, {"type", "VEC3"},
                        {"min", {lo[0], lo[1], lo[2]}}, {"max", {hi[0], hi[1], hi[2]}}});
  attributes["POSITION"] = accessors->size() - 1;
  if (!m.normals.empty()) {
    view = AddView(bin, views, m.normals.data(), n * sizeof(Eigen::Vector3f), kArrayBuffer);
    accessors->push_back({{"bufferView", view}, {"componentType", kFloat}, {"count", n}, {"type", "VEC3"}});
    attributes["NORMAL"] = accessors->size() - 1;
  }
  if (!m.texcoords.empty()) {
    view = AddView(bin, views, m.texcoords.data(), n * sizeof(Eigen::Vector2f), kArrayBuffer);
    accessors->push_back({{"bufferView", view}, {"componentType", kFloat}, {"count", n}, {"type", "VEC2"}});
    attributes["TEXCOORD_0"] = accessors->size() - 1;
  }
  if (n <= 65536) {  // 16-bit indices halve the index data of the many small meshes
    std::vector<uint16_t> idx(m.indices.begin(), m.indices.end());
    view = AddView(bin, views, idx.data(), idx.size() * 2, kElementArrayBuffer);
    accessors->push_back({{"bufferView", view}, {"componentType", kUnsignedShort}, {"count", idx.size()}, {"type", "SCALAR"}});
  } else {
    view = AddView(bin, views, m.indices.data(), m.indices.size() * 4, kElementArrayBuffer);
    accessors->push_back({{"bufferView", view}, {"componentType", kUnsignedInt}, {"count", m.indices.size()}, {"type", "SCALAR"}});
  }
  json prim = {{"attributes", attributes}, {"indices", accessors->size() - 1}, {"mode", 4}};
  if (part.material >= 0) prim["material"] = part.material;
  return prim;
}

// A node's placement: TRS when it is animated (glTF: animated nodes carry TRS, never a matrix;
// placements are rigid), else its matrix, left out when it is the identity.
void SetNodeTransform(const Eigen::Matrix4d& world_from_node, bool animated, json* node) {
  if (animated) {
    const Eigen::Matrix3d r = world_from_node.topLeftCorner<3, 3>();
    const Eigen::Quaterniond q(r);
    (*node)["rotation"] = {q.x(), q.y(), q.z(), q.w()};
    (*node)["translation"] = {world_from_node(0, 3), world_from_node(1, 3), world_from_node(2, 3)};
  } else if (!world_from_node.isIdentity(0.0)) {
    json matrix = json::array();
    for (int c = 0; c < 4; ++c) {
      for (int r = 0; r < 4; ++r) matrix.push_back(world_from_node(r, c));  // glTF: column-major
    }
    (*node)["matrix"] = matrix;
  }
}

// The .glb file: header, the JSON chunk (`text`, padded to 4 bytes) and the BIN chunk when `bin`
// is not empty. Throws std::runtime_error beyond the format's 4 GB.
std::vector<uint8_t> GlbFile(const std::string& text, const std::vector<uint8_t>& bin) {
  std::vector<uint8_t> glb;
  auto u32 = [&glb](uint32_t v) {
    for (int k = 0; k < 4; ++k) glb.push_back(uint8_t(v >> (8 * k)));  // GLB is little-endian
  };
  const size_t total = 12 + 8 + text.size() + (bin.empty() ? 0 : 8 + bin.size());
  if (total > 0xffffffffull) throw std::runtime_error("SceneBuilder: scene exceeds the 4 GB limit of .glb");
  glb.reserve(total);
  glb.insert(glb.end(), {'g', 'l', 'T', 'F'});
  u32(2);
  u32(uint32_t(total));
  u32(uint32_t(text.size()));
  glb.insert(glb.end(), {'J', 'S', 'O', 'N'});
  glb.insert(glb.end(), text.begin(), text.end());
  if (!bin.empty()) {
    u32(uint32_t(bin.size()));
    glb.insert(glb.end(), {'B', 'I', 'N', 0});
    glb.insert(glb.end(), bin.begin(), bin.end());
  }
  return glb;
}

}  // namespace

int SceneBuilder::AddTexture(const std::string& name, int width, int height, int channels, std::vector<uint8_t> pixels,
                             bool nearest) {
  if (width <= 0 || height <= 0 || (channels != 3 && channels != 4) || pixels.size() != size_t(width) * height * channels) {
    throw std::invalid_argument("SceneBuilder::AddTexture('" + name + "'): size does not match width*height*channels");
  }
  textures_.push_back({name, width, height, channels, std::move(pixels), nearest});
  return int(textures_.size()) - 1;
}

int SceneBuilder::AddMaterial(const std::string& name, const Eigen::Vector4f& base_color_factor, int texture,
                              bool double_sided) {
  if (texture < -1 || texture >= int(textures_.size())) {
    throw std::invalid_argument("SceneBuilder::AddMaterial('" + name + "'): texture index out of range");
  }
  materials_.push_back({name, base_color_factor, texture, double_sided});
  return int(materials_.size()) - 1;
}

void SceneBuilder::SetAlphaMask(int material, float cutoff) {
  if (material < 0 || material >= int(materials_.size())) throw std::invalid_argument("SceneBuilder::SetAlphaMask: material index out of range");
  if (!(cutoff >= 0.f && cutoff <= 1.f)) throw std::invalid_argument("SceneBuilder::SetAlphaMask: cutoff must be in [0, 1]");
  materials_[material].alpha_cutoff = cutoff;
}

void SceneBuilder::SetMetallicRoughness(int material, float metallic, float roughness) {
  if (material < 0 || material >= int(materials_.size())) {
    throw std::invalid_argument("SceneBuilder::SetMetallicRoughness: material index out of range");
  }
  if (!(metallic >= 0.f && metallic <= 1.f) || !(roughness >= 0.f && roughness <= 1.f)) {
    throw std::invalid_argument("SceneBuilder::SetMetallicRoughness: factors must be in [0, 1]");
  }
  materials_[material].metallic = metallic;
  materials_[material].roughness = roughness;
}

void SceneBuilder::CheckAnimation(const std::string& who, int node, const std::string& path, const std::vector<float>& times_s,
                                  size_t keys) const {
  if (node < 0 || node >= int(nodes_.size())) throw std::invalid_argument(who + "node index out of range");
  if (times_s.empty() || times_s.size() != keys) throw std::invalid_argument(who + "needs as many times as values");
  for (size_t k = 0; k < times_s.size(); ++k) {
    if (!std::isfinite(times_s[k])) throw std::invalid_argument(who + "times must be finite");
    if (k > 0 && !(times_s[k] > times_s[k - 1])) throw std::invalid_argument(who + "times must increase strictly");
  }
  for (const AnimationData& a : animations_) {
    if (a.node == node && a.path == path) throw std::invalid_argument(who + "node's " + path + " already animated");
  }
}

void SceneBuilder::AddTranslationAnimation(int node, std::vector<float> times_s, std::vector<Eigen::Vector3f> translations) {
  CheckAnimation("SceneBuilder::AddTranslationAnimation: ", node, "translation", times_s, translations.size());
  std::vector<float> values;
  for (const Eigen::Vector3f& t : translations) values.insert(values.end(), {t.x(), t.y(), t.z()});
  animations_.push_back({node, "translation", std::move(times_s), std::move(values)});
}

void SceneBuilder::AddRotationAnimation(int node, std::vector<float> times_s, std::vector<Eigen::Quaternionf> rotations) {
  const std::string who = "SceneBuilder::AddRotationAnimation: ";
  CheckAnimation(who, node, "rotation", times_s, rotations.size());
  std::vector<float> values;
  for (const Eigen::Quaternionf& q : rotations) {
    if (!(q.norm() > 0.f) || !std::isfinite(q.norm())) throw std::invalid_argument(who + "rotations must be finite and non-zero");
    const Eigen::Quaternionf u = q.normalized();
    values.insert(values.end(), {u.x(), u.y(), u.z(), u.w()});
  }
  animations_.push_back({node, "rotation", std::move(times_s), std::move(values)});
}

int SceneBuilder::AddNode(const std::string& name, const std::string& class_name, MeshData mesh, int material,
                          const Eigen::Matrix4d& world_from_node) {
  std::vector<MeshPart> parts;
  parts.push_back({std::move(mesh), material});
  return AddNode(name, class_name, std::move(parts), world_from_node);
}

int SceneBuilder::AddNode(const std::string& name, const std::string& class_name, std::vector<MeshPart> parts,
                          const Eigen::Matrix4d& world_from_node) {
  const std::string who = "SceneBuilder::AddNode('" + name + "'): ";
  if (!class_name.empty() && FindClassByName(class_name) == nullptr) throw std::invalid_argument(who + "unknown class '" + class_name + "'");
  if (parts.empty()) throw std::invalid_argument(who + "no mesh");
  for (const MeshPart& part : parts) {
    const MeshData& mesh = part.mesh;
    if (part.material < -1 || part.material >= int(materials_.size())) throw std::invalid_argument(who + "material index out of range");
    const size_t n = mesh.positions.size();
    if (n == 0 || mesh.indices.empty() || mesh.indices.size() % 3 != 0) throw std::invalid_argument(who + "empty mesh or index count not a multiple of 3");
    if (!mesh.normals.empty() && mesh.normals.size() != n) throw std::invalid_argument(who + "normals size differs from positions");
    if (!mesh.texcoords.empty() && mesh.texcoords.size() != n) throw std::invalid_argument(who + "texcoords size differs from positions");
    for (uint32_t i : mesh.indices) {
      if (i >= n) throw std::invalid_argument(who + "index out of range");
    }
  }
  nodes_.push_back({name, class_name, std::move(parts), world_from_node});
  return int(nodes_.size()) - 1;
}

std::vector<uint8_t> SceneBuilder::ToGlb() const {
  std::vector<uint8_t> bin;
  json views = json::array(), accessors = json::array(), meshes = json::array(), nodes = json::array();
  json images = json::array(), samplers = json::array(), textures = json::array(), materials = json::array();

  for (size_t i = 0; i < textures_.size(); ++i) {
    const TextureData& t = textures_[i];
    std::string mime;
    const std::vector<uint8_t> encoded = EncodeImage(t.name, t.width, t.height, t.channels, t.pixels, jpeg_quality, &mime);
    const int view = AddView(&bin, &views, encoded.data(), encoded.size(), 0);
    images.push_back({{"name", t.name}, {"bufferView", view}, {"mimeType", mime}});
    // 9728 NEAREST, 9729 LINEAR, 9987 LINEAR_MIPMAP_LINEAR, 10497 REPEAT.
    samplers.push_back({{"magFilter", t.nearest ? 9728 : 9729}, {"minFilter", 9987}, {"wrapS", 10497}, {"wrapT", 10497}});
    textures.push_back({{"name", t.name}, {"source", i}, {"sampler", i}});
  }
  for (const MaterialData& m : materials_) {
    json pbr = {{"baseColorFactor", {m.factor[0], m.factor[1], m.factor[2], m.factor[3]}},
                {"metallicFactor", double(m.metallic)},
                {"roughnessFactor", double(m.roughness)}};
    if (m.texture >= 0) pbr["baseColorTexture"] = {{"index", m.texture}};
    json jm = {{"name", m.name}, {"pbrMetallicRoughness", pbr}};
    if (m.double_sided) jm["doubleSided"] = true;
    if (m.alpha_cutoff >= 0.f) {
      jm["alphaMode"] = "MASK";
      jm["alphaCutoff"] = m.alpha_cutoff;
    }
    materials.push_back(jm);
  }
  json scene_nodes = json::array();
  for (size_t i = 0; i < nodes_.size(); ++i) {
    const NodeData& nd = nodes_[i];
    json prims = json::array();
    for (const MeshPart& part : nd.parts) prims.push_back(PrimitiveJson(part, &bin, &views, &accessors));
    meshes.push_back({{"name", nd.name}, {"primitives", prims}});
    json node = {{"name", nd.name}, {"mesh", i}};
    if (!nd.class_name.empty()) node["extras"] = {{"class", nd.class_name}};
    bool animated = false;
    for (const AnimationData& a : animations_) animated = animated || a.node == int(i);
    SetNodeTransform(nd.world_from_node, animated, &node);
    nodes.push_back(node);
    scene_nodes.push_back(i);
  }
  json animation_channels = json::array(), animation_samplers = json::array();
  for (const AnimationData& a : animations_) {
    const float t0 = a.times.front(), t1 = a.times.back();
    int view = AddView(&bin, &views, a.times.data(), a.times.size() * sizeof(float), 0);
    accessors.push_back({{"bufferView", view}, {"componentType", kFloat}, {"count", a.times.size()}, {"type", "SCALAR"},
                         {"min", {t0}}, {"max", {t1}}});
    const size_t input = accessors.size() - 1;
    view = AddView(&bin, &views, a.values.data(), a.values.size() * sizeof(float), 0);
    accessors.push_back({{"bufferView", view}, {"componentType", kFloat}, {"count", a.times.size()},
                         {"type", a.path == "rotation" ? "VEC4" : "VEC3"}});
    animation_samplers.push_back({{"input", input}, {"output", accessors.size() - 1}, {"interpolation", "LINEAR"}});
    animation_channels.push_back({{"sampler", animation_samplers.size() - 1}, {"target", {{"node", a.node}, {"path", a.path}}}});
  }
  while (bin.size() % 4 != 0) bin.push_back(0);

  json doc = {{"asset", {{"version", "2.0"}, {"generator", "rigsim SceneBuilder"}}},
              {"scene", 0},
              {"scenes", json::array({{{"nodes", scene_nodes}}})},
              {"nodes", nodes},
              {"meshes", meshes},
              {"accessors", accessors},
              {"bufferViews", views}};
  if (!bin.empty()) doc["buffers"] = json::array({{{"byteLength", bin.size()}}});
  if (!materials.empty()) doc["materials"] = materials;
  if (!animations_.empty()) {
    doc["animations"] = json::array({{{"name", "motion"}, {"channels", animation_channels}, {"samplers", animation_samplers}}});
  }
  if (!textures.empty()) {
    doc["images"] = images;
    doc["samplers"] = samplers;
    doc["textures"] = textures;
  }
  std::string text = doc.dump();
  while (text.size() % 4 != 0) text.push_back(' ');  // GLB pads the JSON chunk with spaces

  return GlbFile(text, bin);
}

void SceneBuilder::WriteGlb(const std::filesystem::path& path) const {
  const std::vector<uint8_t> glb = ToGlb();
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw std::runtime_error(path.string() + ": cannot open for writing");
  out.write(reinterpret_cast<const char*>(glb.data()), std::streamsize(glb.size()));
  if (!out) throw std::runtime_error(path.string() + ": write failed");
}

}  // namespace rigsim
