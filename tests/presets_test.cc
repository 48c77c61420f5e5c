// Every scene preset, end to end: each renders with every rig generator;
// each preset gives SIFT at least 2000 features per 1280x720 view on average; a ring rig asked
// for a neighbour overlap gets it within +-5 points of the ground truth measured on the renders.
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "dataset/ground_truth.h"
#include "gltf/gltf_loader.h"
#include "labels/cityscapes.h"
#include "procedural/presets.h"
#include "renderer/renderer.h"
#include "rigs/placement.h"
#include "rigs/rig_presets.h"
#include "rigs/trajectories.h"

namespace rigsim {
namespace {

// Shipped assets (tests run from the repository root); procedural_test checks they match the code.
std::string AssetOf(ScenePreset p) { return "assets/scenes/" + std::string(ScenePresetName(p)) + ".glb"; }

const Scene& LoadedScene(ScenePreset p) {
  static std::map<ScenePreset, Scene> cache;
  auto it = cache.find(p);
  if (it == cache.end()) it = cache.emplace(p, LoadGltf(AssetOf(p))).first;
  return it->second;
}

RenderOptions FastOptions() {
  RenderOptions o;
  o.samples_per_pixel = 1;
  o.seed = 1;
  return o;
}

// Fraction of pixels with a surface (range > 0) and fraction with a valid label.
double SurfaceFraction(const RenderedView& v) {
  size_t n = 0;
  for (float r : v.range.data) n += r > 0;
  return double(n) / v.range.data.size();
}

class PresetTest : public testing::TestWithParam<ScenePreset> {};

TEST_P(PresetTest, RendersWithEveryRigGenerator) {
  const Scene& scene = LoadedScene(GetParam());
  const Renderer renderer(scene);
  struct Case {
    std::string name;
    Rig rig;
  };
  std::vector<Case> cases;
  RingRigOptions ring;
  ring.width = 320, ring.height = 180;
  cases.push_back({"ring", MakeRingRig(ring)});
  StereoRigOptions stereo;
  stereo.width = 320, stereo.height = 180;
  cases.push_back({"stereo", MakeStereoRig(stereo)});
  SurroundRigOptions surround;
  surround.width = 320, surround.height = 180;
  cases.push_back({"surround", MakeSurroundRig(surround)});
  WideBaselineRigOptions wide;
  wide.width = 320, wide.height = 180;
  cases.push_back({"wide-baseline", MakeWideBaselineRig(wide)});
  // Trajectory: the ring on a circle and on a straight path, placed automatically.
  PlacementOptions placement;
  placement.num_candidates = 80;
  placement.travel_m = 4.0;
  const auto placed = PlaceRig(scene, cases[0].rig, placement);
  ASSERT_TRUE(placed.has_value()) << "no automatic placement in " << AssetOf(GetParam());
  TrajectoryOptions straight;
  straight.start_world = placed->position_world;
  straight.heading_deg = placed->heading_deg;
  straight.num_frames = 2;
  TrajectoryOptions circle;
  circle.kind = TrajectoryKind::kCircle;
  circle.circle_radius_m = 8.0;
  circle.num_frames = 2;
  circle.start_world = Eigen::Vector3d(0, 1.6, 0);
  std::vector<std::pair<std::string, FramesFile>> trajectories = {
      {"at the origin", MakeStraightTrajectory(Eigen::Vector3d(0, 1.6, 0), 0.0, 1, 0.0)},
      {"straight from the automatic placement", MakeTrajectory(straight)},
      {"circle", MakeTrajectory(circle)}};
  for (const Case& c : cases) {
    for (const auto& [tname, frames] : trajectories) {
      if (c.name != "ring" && tname != "at the origin") continue;  // trajectories once, with the ring
      for (const Frame& f : frames.frames) {
        for (const RigCamera& rc : c.rig.cameras) {
          const RenderedView v = renderer.Render(rc.camera, *rc.cam_from_rig * *f.rig_from_world, FastOptions());
          EXPECT_GT(SurfaceFraction(v), 0.25) << c.name << " " << tname << " frame " << f.name << " " << rc.name;
        }
      }
    }
  }
}

TEST_P(PresetTest, SiftFeaturesAndRingOverlap) {
  const Scene& scene = LoadedScene(GetParam());
  const Renderer renderer(scene);
  RingRigOptions ring;
  ring.num_cameras = 4;
  ring.target_overlap = 0.30;
  ring.radius_m = 0.2;
  ring.distorted_camera = -1;
  const Rigid3d rig_from_world = RigFromWorldAt(Eigen::Vector3d(0, 1.6, 0), 0.0);
  const Rig rig = MakeRingRigInScene(ring, scene, rig_from_world);
  std::vector<RenderedView> views;
  auto sift = cv::SIFT::create();
  double features = 0;
  for (const RigCamera& rc : rig.cameras) {
    views.push_back(renderer.Render(rc.camera, *rc.cam_from_rig * rig_from_world, FastOptions()));
    const RenderedView& v = views.back();
    cv::Mat rgb(v.rgb.height, v.rgb.width, CV_8UC3, const_cast<uint8_t*>(v.rgb.data.data())), gray;
    cv::cvtColor(rgb, gray, cv::COLOR_RGB2GRAY);
    std::vector<cv::KeyPoint> keypoints;
    sift->detect(gray, keypoints);
    features += keypoints.size();
    if (std::getenv("RIGSIM_PRESETS_TEST_DUMP")) {  // look at the views: RIGSIM_PRESETS_TEST_DUMP=1
      cv::Mat bgr;
      cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
      cv::imwrite("/tmp/presets_test_" + std::string(ScenePresetName(GetParam())) + "_" + rc.name + ".png", bgr);
    }
  }
  features /= views.size();
  std::printf("%s: %.0f SIFT features per 1280x720 view\n", std::string(ScenePresetName(GetParam())).c_str(), features);
  EXPECT_GE(features, 2000.0);
  for (size_t i = 0; i + 1 < rig.cameras.size(); ++i) {
    const RigCamera& a = rig.cameras[i];
    const RigCamera& b = rig.cameras[i + 1];
    const Rigid3d b_from_a = *b.cam_from_rig * a.cam_from_rig->Inverse();
    const double ab = CoVisibleFraction(a.camera, views[i].range, b.camera, views[i + 1].range, b_from_a);
    const double ba = CoVisibleFraction(b.camera, views[i + 1].range, a.camera, views[i].range, b_from_a.Inverse());
    std::printf("  %s-%s ground-truth overlap %.1f%% / %.1f%% (asked 30%%)\n", a.name.c_str(), b.name.c_str(), 100 * ab, 100 * ba);
    EXPECT_NEAR(0.5 * (ab + ba), 0.30, 0.05) << a.name << "-" << b.name;
  }
}

INSTANTIATE_TEST_SUITE_P(AllPresets, PresetTest, testing::ValuesIn(AllScenePresets()),
                         [](const testing::TestParamInfo<ScenePreset>& info) { return std::string(ScenePresetName(info.param)); });

}  // namespace
}  // namespace rigsim
