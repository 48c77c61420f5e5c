// The 3D scene of a report: cameras and their fields of view, true and estimated poses, the
// trajectories, the triangulated points, the glTF scene.
#include <fstream>
#include <iterator>

#include "report/report_images.h"
#include "report/report_parts.h"

namespace rigsim::report_parts {
namespace fs = std::filesystem;
using Json = nlohmann::json;

namespace {

Json Vec(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

// The scene file as base64 in data/scene.js; false (and a warning) when it cannot be read.
bool EmbedScene(ReportContext& ctx) {
  const fs::path& scene = ctx.options.scene;
  if (scene.empty()) return false;
  std::ifstream in(scene, std::ios::binary);
  if (!in) {
    ctx.warnings.push_back(scene.string() + ": cannot read the scene; the 3D view shows the rig without it");
    return false;
  }
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.size() < 12 || bytes.compare(0, 4, "glTF") != 0) {
    ctx.warnings.push_back(scene.string() + ": not a binary glTF (.glb); the 3D view shows the rig without it");
    return false;
  }
  WriteDataScript(ctx.dir / "data" / "scene.js", "scene", Base64Encode(bytes));
  return true;
}

}  // namespace

Json SceneData(ReportContext& ctx) {
  const CalibrationRun& run = ctx.run;
  const Rig& rig = run.inputs.rig;
  Json scene;
  scene["glb"] = EmbedScene(ctx) ? Json("data/scene.js") : Json(nullptr);
  scene["scene_name"] = ctx.options.scene.empty() ? run.inputs.frames.scene : ctx.options.scene.filename().string();
  Json cameras = Json::array();
  for (const RigCamera& rc : rig.cameras) {
    Json outline = Json::array();
    for (const Eigen::Vector3d& ray : FieldOfViewOutline(rc.camera)) outline.push_back(Vec(ray));
    cameras.push_back({{"name", rc.name}, {"fov_outline", outline}});
  }
  scene["cameras"] = cameras;
  // The truth: every view's cam_from_world (frame-major), the rig's trajectory.
  if (ctx.HasTruth()) {
    Json truth = Json::array();
    Json trajectory = Json::array();
    for (const Frame& frame : run.inputs.frames.frames) {
      Json per_camera = Json::array();
      for (const RigCamera& rc : rig.cameras) per_camera.push_back(Pose(*rc.cam_from_rig * *frame.rig_from_world));
      truth.push_back(per_camera);
      trajectory.push_back(Vec((*rig.cameras[0].cam_from_rig * *frame.rig_from_world).SourceOriginInTarget()));
    }
    scene["truth_cam_from_world"] = truth;
    scene["truth_trajectory"] = trajectory;  // camera 0's centre per frame
  } else {
    scene["truth_cam_from_world"] = nullptr;
    scene["truth_trajectory"] = nullptr;
  }
  // Per mode: each camera's cam_from_cam0 aligned as evaluate aligns it, the estimated trajectory
  // of camera 0 and the points, both placed in the truth's world.
  Json modes = Json::array();
  for (size_t m = 0; m < run.results.size(); ++m) {
    const RigCalibrationResult& r = run.results[m];
    Json mode = {{"name", r.semantic_mode}};
    Json poses = Json::array();
    const AlignedEstimate* al = ctx.HasTruth() ? &ctx.aligned[m] : nullptr;
    for (size_t c = 0; c < rig.cameras.size(); ++c) {
      if (al) {
        poses.push_back(al->cam_from_cam0[c] ? Json({{"cam_from_cam0", Pose(*al->cam_from_cam0[c])},
                                                     {"rotation_only", bool(al->rotation_only[c])}})
                                             : Json(nullptr));
      } else {
        const auto& pose = r.rig.cameras[c].cam_from_rig;
        poses.push_back(pose ? Json({{"cam_from_cam0", Pose(*pose)}, {"rotation_only", false}}) : Json(nullptr));
      }
    }
    mode["cameras"] = poses;
    Json trajectory = Json::array();
    for (const auto& rig_from_world : r.rig_from_world) {
      if (!rig_from_world) {
        trajectory.push_back(nullptr);
        continue;
      }
      const Eigen::Vector3d centre = rig_from_world->SourceOriginInTarget();
      trajectory.push_back(Vec(al ? al->ToWorld(centre) : centre));
    }
    mode["trajectory"] = trajectory;
    std::vector<float> points;
    if (const RigCalibrationDetails* d = ctx.Details(m)) {
      const size_t total = d->points.size();
      const size_t keep = std::min<size_t>(total, std::max(0, ctx.options.max_points));
      for (size_t i = 0; i < keep; ++i) {
        const Eigen::Vector3d x = al ? al->ToWorld(d->points[i * total / keep]) : d->points[i * total / keep];
        points.insert(points.end(), {float(x.x()), float(x.y()), float(x.z())});
      }
      mode["points_total"] = total;
    }
    mode["points"] = Base64Of(points);
    mode["scale"] = al ? Json(al->scale) : Json(nullptr);
    modes.push_back(mode);
  }
  scene["modes"] = modes;
  return scene;
}

}  // namespace rigsim::report_parts
