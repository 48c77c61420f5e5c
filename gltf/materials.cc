#include <cmath>
#include <string>
#include <tuple>
#include <vector>

#include "gltf/loader.h"

namespace rigsim::gltf {

void Loader::ConvertMaterials() {
  material_uv_.resize(model_.materials.size());
  for (size_t i = 0; i < model_.materials.size(); ++i) {
    const tinygltf::Material& m = model_.materials[i];
    Material out;
    out.name = m.name;
    const auto& pbr = m.pbrMetallicRoughness;
    if (pbr.baseColorFactor.size() == 4) {
      out.base_color_factor = Eigen::Vector4d(pbr.baseColorFactor[0], pbr.baseColorFactor[1], pbr.baseColorFactor[2],
                                              pbr.baseColorFactor[3]).cast<float>();
    }
    const std::string material_label = "material " + std::to_string(i) + " " + Quote(m.name);
    MaterialUvs& uvs = material_uv_[i];
    if (pbr.baseColorTexture.index >= 0) {
      uvs.base_color = ParseTextureInfoUv(pbr.baseColorTexture, material_label + " baseColorTexture");
      out.base_color_texture = ConvertTexture(pbr.baseColorTexture.index);
    }
    ConvertEmission(m, material_label, &out, &uvs);
    if (m.normalTexture.index >= 0) {
      const std::string where = material_label + " normalTexture";
      if (!std::isfinite(m.normalTexture.scale)) Fail(where + ": scale is not finite");
      uvs.normal = ParseTextureInfoUv(m.normalTexture, where);
      out.normal_texture = ConvertTexture(m.normalTexture.index);
      out.normal_scale = float(m.normalTexture.scale);
    }
    if (m.occlusionTexture.index >= 0) {
      const std::string where = material_label + " occlusionTexture";
      const double strength = m.occlusionTexture.strength;
      if (!(strength >= 0.0 && strength <= 1.0)) Fail(where + ": strength must be in [0, 1], got " + std::to_string(strength));
      uvs.occlusion = ParseTextureInfoUv(m.occlusionTexture, where);
      out.occlusion_texture = ConvertTexture(m.occlusionTexture.index);
      out.occlusion_strength = float(strength);
    }
    if (m.alphaMode == "MASK") {
      out.alpha_mode = AlphaMode::kMask;
    } else if (m.alphaMode == "BLEND") {
      out.alpha_mode = AlphaMode::kBlend;
    }
    out.alpha_cutoff = float(m.alphaCutoff);
    out.double_sided = m.doubleSided;
    for (const auto& [factor, name, field] : {std::tuple{pbr.metallicFactor, "metallicFactor", &out.metallic},
                                              std::tuple{pbr.roughnessFactor, "roughnessFactor", &out.roughness}}) {
      if (!(factor >= 0.0 && factor <= 1.0)) {
        Fail(material_label + ": pbrMetallicRoughness " + name + " must be in [0, 1], got " + std::to_string(factor));
      }
      *field = float(factor);
    }
    // The texture scales the factors (roughness by its G channel, metallic by its B): read as the
    // factors alone, a surface is never glossier than the file makes it.
    if (pbr.metallicRoughnessTexture.index >= 0) Ignore("metallicRoughnessTexture (materials; its factors are used)");
    for (const auto& [name, value] : m.extensions) {
      if (name == "KHR_materials_unlit") {
        out.unlit = true;
      } else if (name == "KHR_materials_emissive_strength") {
        // read by ConvertEmission
      } else {
        Ignore("material extension " + name);
      }
    }
    scene_.materials.push_back(std::move(out));
  }
  // ConvertTexture failed on every refused image a texture samples: the rest are used by none.
  for (const auto& [index, why] : image_checks_.refused) Warn(why + "; no texture rigsim uses samples it, so it is skipped");
}

// The coordinates a textureInfo samples: its texCoord, or KHR_texture_transform's.
template <typename TextureInfo>
TextureUv Loader::ParseTextureInfoUv(const TextureInfo& info, const std::string& where) {
  TextureUv uv;
  uv.set = info.texCoord;
  for (const auto& [name, value] : info.extensions) {
    if (name == "KHR_texture_transform") {
      uv = ParseTextureTransform(value, where, uv.set);
    } else {
      Ignore("texture-info extension " + name);
    }
  }
  if (uv.set < 0) Fail(where + ": texCoord " + std::to_string(uv.set) + " is negative");
  return uv;
}

// emissiveFactor (glTF: each in [0, 1]), scaled by KHR_materials_emissive_strength (>= 0), and the
// emissive texture with its coordinates.
void Loader::ConvertEmission(const tinygltf::Material& m, const std::string& where, Material* out, MaterialUvs* uvs) {
  const std::vector<double>& f = m.emissiveFactor;
  if (f.size() != 3) Fail(where + ": emissiveFactor must have 3 numbers, got " + std::to_string(f.size()));
  for (double v : f) {
    if (!(v >= 0.0) || !std::isfinite(v)) Fail(where + ": emissiveFactor must be finite and >= 0, got " + std::to_string(v));
    if (v > 1.0) Warn(where + ": emissiveFactor " + std::to_string(v) + " is above glTF's maximum of 1; used as given");
  }
  double strength = 1.0;
  if (auto it = m.extensions.find("KHR_materials_emissive_strength"); it != m.extensions.end()) {
    const tinygltf::Value& ext = it->second;
    if (!ext.IsObject()) Fail(where + ": KHR_materials_emissive_strength is not an object");
    if (ext.Has("emissiveStrength")) {
      const tinygltf::Value& v = ext.Get("emissiveStrength");
      strength = v.IsNumber() ? v.GetNumberAsDouble() : -1.0;
      if (!(strength >= 0.0) || !std::isfinite(strength)) {
        Fail(where + ": KHR_materials_emissive_strength: emissiveStrength must be a finite number >= 0");
      }
    }
  }
  out->emissive = (Eigen::Vector3d(f[0], f[1], f[2]) * strength).cast<float>();
  if (m.emissiveTexture.index >= 0 && out->emissive != Eigen::Vector3f::Zero()) {
    uvs->emissive = ParseTextureInfoUv(m.emissiveTexture, where + " emissiveTexture");
    out->emissive_texture = ConvertTexture(m.emissiveTexture.index);
  }
}

// KHR_texture_transform on a textureInfo: uv' = T(offset) * R(rotation) * S(scale) * uv, and an
// optional texCoord that overrides the textureInfo's `texcoord_set`.
//
// Rotation: the extension rotates UVs counter-clockwise *in UV space*, where v points down, so
// (u, v) -> (cos r * u + sin r * v, -sin r * u + cos r * v): at 90 deg, (1, 0) -> (0, -1). This is
// what the Khronos sample viewer, three.js, Babylon.js, Blender and CesiumGltf compute and what the
// TextureTransformTest sample model checks; the GLSL listing in the extension's README shows the
// transpose (a counter-clockwise turn in a v-up space), a known erratum (KhronosGroup/glTF #1563).
TextureUv Loader::ParseTextureTransform(const tinygltf::Value& ext, const std::string& where, int texcoord_set) {
  const std::string w = where + ": KHR_texture_transform";
  if (!ext.IsObject()) Fail(w + " is not an object");
  auto vec2 = [&](const char* key, Eigen::Vector2d fallback) {
    if (!ext.Has(key)) return fallback;
    const tinygltf::Value& v = ext.Get(key);
    if (!v.IsArray() || v.ArrayLen() != 2 || !v.Get(0).IsNumber() || !v.Get(1).IsNumber()) {
      Fail(w + ": " + key + " must be an array of 2 numbers");
    }
    const Eigen::Vector2d out(v.Get(0).GetNumberAsDouble(), v.Get(1).GetNumberAsDouble());
    if (!out.allFinite()) Fail(w + ": " + key + " is not finite");
    return out;
  };
  const Eigen::Vector2d offset = vec2("offset", Eigen::Vector2d::Zero());
  const Eigen::Vector2d scale = vec2("scale", Eigen::Vector2d::Ones());
  double rotation = 0.0;
  if (ext.Has("rotation")) {
    const tinygltf::Value& r = ext.Get("rotation");
    if (!r.IsNumber() || !std::isfinite(r.GetNumberAsDouble())) Fail(w + ": rotation must be a finite number (radians)");
    rotation = r.GetNumberAsDouble();
  }
  TextureUv out;
  out.set = texcoord_set;
  if (ext.Has("texCoord")) {
    const tinygltf::Value& t = ext.Get("texCoord");
    if (!t.IsInt() || t.GetNumberAsInt() < 0) Fail(w + ": texCoord must be a non-negative integer");
    out.set = t.GetNumberAsInt();
  }
  const double c = std::cos(rotation), s = std::sin(rotation);
  Eigen::Matrix2d rot;
  rot << c, s, -s, c;
  out.uv_from_texcoord.leftCols<2>() = rot * scale.asDiagonal();
  out.uv_from_texcoord.col(2) = offset;
  return out;
}

}  // namespace rigsim::gltf
