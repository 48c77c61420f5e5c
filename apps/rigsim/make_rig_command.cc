#include <cstdio>
#include <filesystem>

#include "apps/rigsim/commands.h"
#include "geometry/rig.h"
#include "scenes/gltf_loader.h"
#include "scenes/rig_generators.h"

namespace rigsim::cli {

void AddMakeRigCommand(CLI::App& app) {
  struct Args {
    std::string type = "ring";
    RingRigOptions ring;
    StereoRigOptions stereo;
    SurroundRigOptions surround;
    WideBaselineRigOptions wide;
    double overlap_percent = 0.0;
    double hfov_deg = 95.0;
    RigPerturbation perturb;
    std::vector<double> position = {0.0, 1.6, 0.0};
    double heading_deg = 0.0;
    std::string trajectory = "straight";
    double circle_radius_m = 10.0;
    int frames = 1;
    double step_m = 2.0;
    std::string scene;
    PlacementOptions placement;
    std::string rig_out, frames_out;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "make-rig",
      "Write a rig (rig.json) and its placement in a scene over K frames (frames.json) for `rigsim render`.\n"
      "Types:\n"
      "  ring           cam0..camN-1 on a horizontal circle facing outwards, left to right (--spacing or --overlap)\n"
      "  stereo         left/right, parallel, --baseline apart\n"
      "  surround       vehicle-like: front (OPENCV), right and left (OPENCV_FISHEYE, --side-fov > 180 ok), back (PINHOLE)\n"
      "  wide-baseline  cam0/cam1 --baseline apart, toed in by --convergence in total\n"
      "With --scene the rig is placed automatically on the ground where every camera sees structure\n"
      "and no surface is closer than --clearance (overrides --position and --heading).");
  cmd->add_option("type,--type", args->type, "rig type")
      ->capture_default_str()
      ->check(CLI::IsMember({"ring", "stereo", "surround", "wide-baseline"}));
  RingRigOptions& r = args->ring;
  cmd->add_option("--cameras", r.num_cameras, "ring: number of cameras")->capture_default_str()->check(CLI::Range(1, 64));
  cmd->add_option("--spacing", r.yaw_spacing_deg, "ring: yaw between neighbouring cameras (deg)")->capture_default_str();
  cmd->add_option("--overlap", args->overlap_percent,
                  "ring: target overlap between neighbours (percent of the image, at infinity; overrides --spacing)")
      ->check(CLI::Range(0.0, 99.0));
  cmd->add_option("--hfov", args->hfov_deg, "horizontal field of view of the perspective cameras (deg; ring default 95, "
                                            "stereo 80, wide-baseline 70, surround front 100)");
  cmd->add_option("--radius", r.radius_m, "ring: radius (m)")->capture_default_str();
  cmd->add_option("--distorted", r.distorted_camera, "ring: index of the camera with barrel distortion (-1 = none)")
      ->capture_default_str();
  cmd->add_option("--k1", r.k1, "ring: its OPENCV k1")->capture_default_str();
  cmd->add_option("--k2", r.k2, "ring: its OPENCV k2")->capture_default_str();
  cmd->add_option("--baseline", args->stereo.baseline_m, "stereo / wide-baseline: distance between the cameras (m; "
                                                         "defaults 0.12 and 2.0)");
  cmd->add_option("--convergence", args->wide.convergence_deg, "wide-baseline: angle between the optical axes (deg)")
      ->capture_default_str();
  cmd->add_option("--side-fov", args->surround.side_fov_deg, "surround: field of view of the side fisheyes (deg)")
      ->capture_default_str();
  cmd->add_option("--vehicle", args->surround.length_m, "surround: distance between front and back cameras (m)")
      ->capture_default_str();
  cmd->add_option("--width", r.width, "image width (px)")->capture_default_str();
  cmd->add_option("--height", r.height, "image height (px)")->capture_default_str();
  cmd->add_option("--jitter-deg", args->perturb.rotation_deg, "random mounting error: rotation up to this (deg)")
      ->capture_default_str();
  cmd->add_option("--jitter-m", args->perturb.translation_m, "random mounting error: translation up to this (m)")
      ->capture_default_str();
  cmd->add_option("--seed", args->perturb.seed, "seed of the mounting error and of the automatic placement")
      ->capture_default_str();
  cmd->add_option("--position", args->position, "rig position in the world at frame 0: x,y,z (m, glTF +Y up)")
      ->delimiter(',')
      ->expected(3)
      ->capture_default_str();
  cmd->add_option("--heading", args->heading_deg, "rig heading (deg; 0 = world -Z, 90 = world +X)")
      ->capture_default_str();
  cmd->add_option("--trajectory", args->trajectory, "path over the frames: straight or circle")
      ->capture_default_str()
      ->check(CLI::IsMember({"straight", "circle"}));
  cmd->add_option("--circle-radius", args->circle_radius_m, "circle: radius (m; > 0 turns left, < 0 right)")
      ->capture_default_str();
  cmd->add_option("--frames", args->frames, "number of frames; the rig moves --step along the path between them")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));
  cmd->add_option("--step", args->step_m, "distance moved per frame (m)")->capture_default_str();
  cmd->add_option("--scene", args->scene, "place the rig automatically in this glTF scene")->check(CLI::ExistingFile);
  cmd->add_option("--clearance", args->placement.min_clearance_m, "placement: no surface closer along a camera axis (m)")
      ->capture_default_str();
  cmd->add_option("--rig-out", args->rig_out, "rig.json to write")->required();
  cmd->add_option("--frames-out", args->frames_out, "frames.json to write")->required();
  cmd->callback([args, cmd] {
    const bool hfov_given = cmd->count("--hfov") > 0;
    const bool baseline_given = cmd->count("--baseline") > 0;
    Rig rig;
    if (args->type == "ring") {
      RingRigOptions o = args->ring;
      if (hfov_given) o.hfov_deg = args->hfov_deg;
      o.target_overlap = args->overlap_percent / 100.0;
      rig = MakeRingRig(o);
    } else if (args->type == "stereo") {
      StereoRigOptions o = args->stereo;
      if (hfov_given) o.hfov_deg = args->hfov_deg;
      o.width = args->ring.width;
      o.height = args->ring.height;
      rig = MakeStereoRig(o);
    } else if (args->type == "surround") {
      SurroundRigOptions o = args->surround;
      if (hfov_given) o.front_hfov_deg = args->hfov_deg;
      o.width = args->ring.width;
      o.height = args->ring.height;
      rig = MakeSurroundRig(o);
    } else {
      WideBaselineRigOptions o = args->wide;
      if (hfov_given) o.hfov_deg = args->hfov_deg;
      if (baseline_given) o.baseline_m = args->stereo.baseline_m;
      o.width = args->ring.width;
      o.height = args->ring.height;
      rig = MakeWideBaselineRig(o);
    }
    if (args->perturb.rotation_deg > 0 || args->perturb.translation_m > 0) PerturbRig(rig, args->perturb);

    TrajectoryOptions t;
    t.kind = args->trajectory == "circle" ? TrajectoryKind::kCircle : TrajectoryKind::kStraight;
    t.start_world = Eigen::Vector3d(args->position[0], args->position[1], args->position[2]);
    t.heading_deg = args->heading_deg;
    t.num_frames = args->frames;
    t.step_m = args->step_m;
    t.circle_radius_m = args->circle_radius_m;
    std::string scene_name;
    if (!args->scene.empty()) {
      const Scene scene = LoadGltf(args->scene);
      PlacementOptions p = args->placement;
      p.height_m = args->position[1] > 0 && cmd->count("--position") ? args->position[1] : p.height_m;
      p.seed = args->perturb.seed;
      if (t.kind == TrajectoryKind::kStraight) p.travel_m = (args->frames - 1) * std::abs(args->step_m);
      const std::optional<RigPlacement> placed = PlaceRig(scene, rig, p);
      if (!placed) {
        throw std::runtime_error(args->scene + ": no place found where the rig stands on the ground with " +
                                 std::to_string(p.min_clearance_m) + " m clearance; try a smaller --clearance or fewer --frames");
      }
      t.start_world = placed->position_world;
      t.heading_deg = placed->heading_deg;
      if (args->type == "ring" && args->overlap_percent > 0) {
        // Re-solve the spacing for the ground-truth overlap in this scene at this place (sky and
        // occluders change it from the angular value).
        RingRigOptions o = args->ring;
        if (hfov_given) o.hfov_deg = args->hfov_deg;
        o.target_overlap = args->overlap_percent / 100.0;
        rig = MakeRingRigInScene(o, scene, RigFromWorldAt(t.start_world, t.heading_deg));
        if (args->perturb.rotation_deg > 0 || args->perturb.translation_m > 0) PerturbRig(rig, args->perturb);
      }
      scene_name = std::filesystem::path(args->scene).filename().string();
      std::printf("placed at (%.2f, %.2f, %.2f), heading %.1f deg (%.0f%% of probe rays see structure)\n",
                  placed->position_world.x(), placed->position_world.y(), placed->position_world.z(), placed->heading_deg,
                  100.0 * placed->score);
    }
    FramesFile frames = MakeTrajectory(t);
    frames.scene = scene_name;
    WriteRig(rig, args->rig_out);
    WriteFrames(frames, args->frames_out);
    std::printf("wrote %s (%s, %zu cameras) and %s (%zu frames, %s)\n", args->rig_out.c_str(), args->type.c_str(),
                rig.cameras.size(), args->frames_out.c_str(), frames.frames.size(), args->trajectory.c_str());
  });
}

}  // namespace rigsim::cli
