#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "apps/rigsim/commands.h"
#include "apps/rigsim/render_support.h"
#include "dataset/dataset.h"
#include "geometry/rig.h"
#include "gltf/gltf_loader.h"
#include "gltf/scene_cameras.h"
#include "rigs/placement.h"
#include "rigs/rig_presets.h"
#include "rigs/trajectories.h"

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
    std::string from_gltf;
    std::string rig_out, frames_out, out;
    bool force = false;
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
      "and no surface is closer than --clearance (overrides --position and --heading).\n"
      "With --from-gltf SCENE the rig is the perspective cameras that SCENE places on its nodes instead\n"
      "(PINHOLE, --width x --height, field of view from each camera's yfov and aspectRatio; cam_from_rig\n"
      "relative to the first camera in file order) and frames.json holds one frame with the rig where the\n"
      "file puts it, so `rigsim render` reproduces the file's views.\n"
      "Output: --rig-out and --frames-out, or --out DIR for DIR/rig.json and DIR/frames.json.");
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
  cmd->add_option("--distorted", r.distorted_camera,
                  "ring: index of the camera with barrel distortion (-1 = none; a one-camera ring has none unless given)")
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
  CLI::Option* from_gltf =
      cmd->add_option("--from-gltf", args->from_gltf,
                      "take the rig from the perspective cameras of this glTF file (see above); rig type, "
                      "camera, placement and trajectory options do not apply")
          ->check(CLI::ExistingFile);
  for (const char* name : {"type", "--cameras", "--spacing", "--overlap", "--hfov", "--radius", "--distorted", "--k1", "--k2",
                           "--baseline", "--convergence", "--side-fov", "--vehicle", "--position", "--heading",
                           "--trajectory", "--circle-radius", "--frames", "--step", "--scene", "--clearance"}) {
    from_gltf->excludes(cmd->get_option(name));
  }
  CLI::Option* rig_out = cmd->add_option("--rig-out", args->rig_out, "rig.json to write");
  CLI::Option* frames_out = cmd->add_option("--frames-out", args->frames_out, "frames.json to write");
  cmd->add_option("--out", args->out,
                  "instead of --rig-out and --frames-out: folder to write rig.json and frames.json into (appears "
                  "complete or not at all; see --force)")
      ->excludes(rig_out)
      ->excludes(frames_out);
  cmd->add_flag("--force", args->force, "with --out: replace an existing folder");
  cmd->callback([args, cmd] {
    // Where to write, checked before any work.
    if (args->out.empty() && (args->rig_out.empty() || args->frames_out.empty())) {
      throw CLI::ValidationError("make-rig", "give --out DIR, or both --rig-out FILE and --frames-out FILE");
    }
    if (!args->out.empty() && std::filesystem::exists(args->out) && !args->force) {
      throw std::runtime_error(args->out + ": already exists (use --force to replace it)");
    }
    const auto write = [&](const Rig& rig, const FramesFile& frames, const std::string& what) {
      std::string rig_path = args->rig_out, frames_path = args->frames_out;
      if (!args->out.empty()) {
        StagedOutput staged(args->out, args->force);
        WriteRig(rig, staged.staging_dir() / "rig.json");
        WriteFrames(frames, staged.staging_dir() / "frames.json");
        staged.Commit();
        rig_path = (std::filesystem::path(args->out) / "rig.json").string();
        frames_path = (std::filesystem::path(args->out) / "frames.json").string();
      } else {
        WriteRig(rig, rig_path);
        WriteFrames(frames, frames_path);
      }
      std::printf("wrote %s (%s, %zu cameras) and %s (%zu frames, %s)\n", rig_path.c_str(), what.c_str(),
                  rig.cameras.size(), frames_path.c_str(), frames.frames.size(),
                  args->from_gltf.empty() ? args->trajectory.c_str() : "the file's camera poses");
    };

    if (!args->from_gltf.empty()) {
      const Scene scene = LoadSceneVerbose(args->from_gltf);  // its warnings name the cameras it skipped
      SceneCameraRig from_file = RigFromSceneCameras(scene, args->ring.width, args->ring.height);
      for (const std::string& w : from_file.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
      if (args->perturb.rotation_deg > 0 || args->perturb.translation_m > 0) PerturbRig(from_file.rig, args->perturb);
      for (const RigCamera& c : from_file.rig.cameras) {
        const Eigen::Vector3d centre = (*c.cam_from_rig * *from_file.frames.frames[0].rig_from_world).SourceOriginInTarget();
        std::printf("  %-12s PINHOLE %dx%d  fx %.2f fy %.2f  at (%.3f, %.3f, %.3f)\n", c.name.c_str(), c.camera.width(),
                    c.camera.height(), c.camera.fx(), c.camera.fy(), centre.x(), centre.y(), centre.z());
      }
      write(from_file.rig, from_file.frames, "from " + std::filesystem::path(args->from_gltf).filename().string());
      return;
    }

    const bool hfov_given = cmd->count("--hfov") > 0;
    const bool baseline_given = cmd->count("--baseline") > 0;
    Rig rig;
    if (args->type == "ring") {
      RingRigOptions o = args->ring;
      if (hfov_given) o.hfov_deg = args->hfov_deg;
      // The default distorted camera (index 1) only exists from two cameras on.
      if (cmd->count("--distorted") == 0 && o.distorted_camera >= o.num_cameras) o.distorted_camera = -1;
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
    write(rig, frames, args->type);
  });
}

}  // namespace rigsim::cli
