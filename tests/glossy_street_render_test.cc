// The presets' glass and puddles end to end: a street generated with them, loaded as render loads
// it and rendered. A puddle and a shop window show a known red target where the law of reflection
// puts it, and keep their own ground truth; the same views without them show no target.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "gltf/gltf_loader.h"
#include "procedural/presets.h"
#include "renderer/render_test_scenes.h"
#include "renderer/renderer.h"
#include "renderer/shading.h"
#include "testing/temp_dir.h"

namespace rigsim {
namespace {

constexpr uint8_t kBuilding = 11;

Scene LoadStreet(const ScenePresetOptions& o) {
  const TempDir dir;
  WriteScenePreset(o, dir / "street.glb");
  return LoadGltf(dir / "street.glb");
}

// The meshes of `scene` that `keep` accepts (materials and textures as they are).
template <class Keep>
Scene Only(const Scene& scene, Keep&& keep) {
  Scene out = scene;
  out.meshes.clear();
  for (const SceneMesh& m : scene.meshes) {
    if (keep(m)) out.meshes.push_back(m);
  }
  return out;
}

bool Glossy(const Scene& scene, const SceneMesh& m) { return GlossOf(scene.materials[size_t(m.material)]) > 0; }

// A pinhole camera at `eye` (glTF world) whose principal point, the centre of pixel (80, 60),
// looks at `at`, the image's up towards +Y.
struct View {
  Camera camera = Camera(CameraModelId::kPinhole, 161, 121, {200, 200, 80, 60});
  Rigid3d cam_from_world;
};
View LookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& at) {
  const Eigen::Vector3d z = (at - eye).normalized();
  const Eigen::Vector3d y = (-Eigen::Vector3d::UnitY() + z * z.y()).normalized();  // down, across the view
  Eigen::Matrix3d cam_from_world;
  cam_from_world.row(0) = y.cross(z);
  cam_from_world.row(1) = y;
  cam_from_world.row(2) = z;
  View v;
  v.cam_from_world = Rigid3d(Eigen::Quaterniond(cam_from_world), -(cam_from_world * eye));
  return v;
}

// Adds a 1 m unlit red square centred at `centre`, facing `towards`.
void AddRedTarget(Scene& scene, const Eigen::Vector3d& centre, const Eigen::Vector3d& towards) {
  const Eigen::Vector3f c = centre.cast<float>(), n = towards.normalized().cast<float>();
  const Eigen::Vector3f u = n.cross(Eigen::Vector3f::UnitY()).normalized() * 0.5f, v = n.cross(u).normalized() * 0.5f;
  const int red = AddMaterial(scene, Eigen::Vector4f(1, 0, 0, 1));
  scene.materials[size_t(red)].unlit = true;
  AddQuad(scene, c - u - v, c + u - v, c + u + v, c - u + v, kCar, 999, red);
}

struct Pixel {
  std::array<int, 3> rgb;
  uint8_t label;
  uint16_t instance;
};
Pixel CentreOf(const Scene& scene, const View& view) {
  RenderOptions o;
  o.samples_per_pixel = 4;
  o.seed = 1;
  o.shadows = false;  // so that the target changes nothing but what the mirror shows
  const RenderedView r = Renderer(scene).Render(view.camera, view.cam_from_world, o);
  return {{r.rgb.at(80, 60, 0), r.rgb.at(80, 60, 1), r.rgb.at(80, 60, 2)}, r.label.at(80, 60), r.instance.at(80, 60)};
}

// Renders `scene` from `view` with and without the target. Where `mirrors`, the centre pixel
// takes the target's colour (red above green and blue by `margin`; without the target it was not
// red); elsewhere the target changes nothing there. The ground truth stays the surface's.
void ExpectMirrorShowsTarget(const Scene& scene, const View& view, const Eigen::Vector3d& target, const Eigen::Vector3d& towards,
                             bool mirrors, int margin) {
  Scene with = scene;
  AddRedTarget(with, target, towards);
  const Pixel a = CentreOf(scene, view), b = CentreOf(with, view);
  const auto redness = [](const std::array<int, 3>& c) { return c[0] - std::max(c[1], c[2]); };
  if (mirrors) {
    EXPECT_GT(redness(b.rgb), margin) << "with the target: " << b.rgb[0] << " " << b.rgb[1] << " " << b.rgb[2];
    EXPECT_LT(redness(a.rgb), 10) << "without: " << a.rgb[0] << " " << a.rgb[1] << " " << a.rgb[2];
  } else {
    EXPECT_EQ(b.rgb, a.rgb);
  }
  EXPECT_EQ(b.label, a.label);
  EXPECT_EQ(b.instance, a.instance);
}

TEST(GlossyStreetRender, APuddleMirrorsWhatStandsAboveIt) {
  ScenePresetOptions o;
  o.wet = 0.15;
  const Scene street = LoadStreet(o);
  // The road only (nothing in the way), and on it the puddle whose rim lies furthest from its centre
  // at its nearest (the fan's centre is the vertex of most triangles).
  const Scene road = Only(street, [](const SceneMesh& m) { return m.class_id == kRoad; });
  Eigen::Vector3d centre;
  float best = 0;
  for (const SceneMesh& m : road.meshes) {
    if (!Glossy(road, m)) continue;
    // A puddle is a fan: consecutive triangles that start at its centre.
    for (size_t i = 0; i + 2 < m.indices.size();) {
      const Eigen::Vector3f c = m.positions[m.indices[i]];
      float nearest = std::numeric_limits<float>::infinity();
      for (; i + 2 < m.indices.size() && m.positions[m.indices[i]] == c; i += 3) {
        nearest = std::min({nearest, (m.positions[m.indices[i + 1]] - c).norm(), (m.positions[m.indices[i + 2]] - c).norm()});
      }
      if (nearest > best) best = nearest, centre = c.cast<double>();
    }
  }
  ASSERT_GT(best, 0.25f) << "no puddle";
  // Seen at a grazing angle along the road, as a car's camera sees it; the target stands where the
  // reflected ray goes, 4 m beyond the puddle and 1 m up.
  const Eigen::Vector3d eye = centre + Eigen::Vector3d(0, 1.5, centre.z() > 0 ? -6 : 6);
  const Eigen::Vector3d d = (centre - eye).normalized(), reflected(d.x(), -d.y(), d.z());
  const Eigen::Vector3d target = centre + 4 * reflected;
  const View view = LookAt(eye, centre);
  SCOPED_TRACE("puddle at " + std::to_string(centre.x()) + ", " + std::to_string(centre.z()));
  EXPECT_EQ(CentreOf(road, view).label, kRoad);
  ExpectMirrorShowsTarget(road, view, target, -reflected, true, 50);
  // The dry road beneath the puddle shows no target.
  const Scene dry = Only(road, [&](const SceneMesh& m) { return !Glossy(road, m); });
  ExpectMirrorShowsTarget(dry, view, target, -reflected, false, 0);
}

TEST(GlossyStreetRender, AShopWindowMirrorsTheStreet) {
  ScenePresetOptions o;
  o.glass = true;
  const Scene street = LoadStreet(o);
  // The widest pane of a shop window (its middle below 3 m) near the middle of the street.
  const SceneMesh* shop = nullptr;
  Eigen::Vector3d centre, normal;
  float widest = 0;
  for (const SceneMesh& m : street.meshes) {
    if (m.class_id != kBuilding || !Glossy(street, m)) continue;
    for (size_t q = 0; q + 3 < m.positions.size(); q += 4) {  // one quad per pane
      const Eigen::Vector3f c = 0.25f * (m.positions[q] + m.positions[q + 1] + m.positions[q + 2] + m.positions[q + 3]);
      const float w = (m.positions[q + 1] - m.positions[q]).norm();
      if (c.y() < 3.f && std::abs(c.z()) < 30.f && w > widest) {
        widest = w, shop = &m, centre = c.cast<double>(), normal = m.normals[q].cast<double>();
      }
    }
  }
  ASSERT_NE(shop, nullptr) << "no shop window";
  // Its building alone, seen at a grazing angle from 1.5 m in front of it and 8 m along it.
  const uint16_t instance = shop->instance_id;
  const Scene building = Only(street, [&](const SceneMesh& m) { return m.instance_id == instance; });
  const Eigen::Vector3d along = normal.cross(Eigen::Vector3d::UnitY()).normalized();
  const Eigen::Vector3d eye = centre + 1.5 * normal + 8 * along;
  const Eigen::Vector3d d = (centre - eye).normalized(), reflected = d - 2 * d.dot(normal) * normal;
  const Eigen::Vector3d target = centre + 3 * reflected;
  const View view = LookAt(eye, centre);
  const Pixel seen = CentreOf(building, view);
  EXPECT_EQ(seen.label, kBuilding);
  EXPECT_EQ(seen.instance, instance);
  ExpectMirrorShowsTarget(building, view, target, -reflected, true, 50);
  const Scene without_glass = Only(building, [&](const SceneMesh& m) { return !Glossy(building, m); });
  ExpectMirrorShowsTarget(without_glass, view, target, -reflected, false, 0);
}

}  // namespace
}  // namespace rigsim
