#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "apps/rigsim/commands.h"
#include "apps/rigsim/render_support.h"
#include "dataset/dataset.h"
#include "geometry/rig.h"
#include "gltf/gltf_loader.h"
#include "gltf/scene_cameras.h"
#include "rigs/rig_spec.h"

namespace rigsim::cli {
namespace {

// What make-rig's options set.
struct MakeRigArgs {
  std::string type = "ring";
  RingRigOptions ring;  // also the image size of every type
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
  std::string lens = "preset";
  double lens_k1 = -0.25;
  double fisheye_fov_deg = 190.0;
  std::string from_gltf;
  std::string rig_out, frames_out, out;
  bool force = false;
  // Capture timing: "SECONDS" for every camera or "CAMERA=SECONDS" for one (repeatable).
  std::vector<std::string> time_offset, readout, readout_direction, exposure;
};

constexpr const char* kDescription =
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
    "Output: --rig-out and --frames-out, or --out DIR for DIR/rig.json and DIR/frames.json.";

// The rig: its type and the options of each type, image size, mounting errors.
void AddRigOptions(CLI::App* cmd, MakeRigArgs& a) {
  cmd->add_option("type,--type", a.type, "rig type")
      ->capture_default_str()
      ->check(CLI::IsMember({"ring", "stereo", "surround", "wide-baseline"}));
  RingRigOptions& r = a.ring;
  cmd->add_option("--cameras", r.num_cameras, "ring: number of cameras")->capture_default_str()->check(CLI::Range(1, 64));
  cmd->add_option("--spacing", r.yaw_spacing_deg, "ring: yaw between neighbouring cameras (deg)")->capture_default_str();
  cmd->add_option("--overlap", a.overlap_percent,
                  "ring: target overlap between neighbours (percent of the image, at infinity; overrides --spacing)")
      ->check(CLI::Range(0.0, 99.0));
  cmd->add_option("--hfov", a.hfov_deg, "horizontal field of view of the perspective cameras (deg; ring default 95, "
                                        "stereo 80, wide-baseline 70, surround front 100)");
  cmd->add_option("--radius", r.radius_m, "ring: radius (m)")->capture_default_str();
  cmd->add_option("--distorted", r.distorted_camera,
                  "ring: index of the camera with barrel distortion (-1 = none; a one-camera ring has none unless given)")
      ->capture_default_str();
  cmd->add_option("--k1", r.k1, "ring: its OPENCV k1")->capture_default_str();
  cmd->add_option("--k2", r.k2, "ring: its OPENCV k2")->capture_default_str();
  cmd->add_option("--baseline", a.stereo.baseline_m, "stereo / wide-baseline: distance between the cameras (m; "
                                                     "defaults 0.12 and 2.0)");
  cmd->add_option("--convergence", a.wide.convergence_deg, "wide-baseline: angle between the optical axes (deg)")
      ->capture_default_str();
  cmd->add_option("--side-fov", a.surround.side_fov_deg, "surround: field of view of the side fisheyes (deg)")
      ->capture_default_str();
  cmd->add_option("--vehicle", a.surround.length_m, "surround: distance between front and back cameras (m)")
      ->capture_default_str();
  cmd->add_option("--lens", a.lens,
                  "every camera's lens instead of the type's own: pinhole, opencv (barrel distortion --lens-k1)\n"
                  "or fisheye (Kannala-Brandt over --fisheye-fov); preset keeps the type's lenses")
      ->capture_default_str()
      ->check(CLI::IsMember({"preset", "pinhole", "opencv", "fisheye"}));
  cmd->add_option("--lens-k1", a.lens_k1, "--lens opencv: k1 (k2 = -0.24 k1)")->capture_default_str();
  cmd->add_option("--fisheye-fov", a.fisheye_fov_deg, "--lens fisheye: horizontal field of view (deg, > 180 ok)")
      ->capture_default_str();
  cmd->add_option("--width", r.width, "image width (px)")->capture_default_str();
  cmd->add_option("--height", r.height, "image height (px)")->capture_default_str();
  cmd->add_option("--jitter-deg", a.perturb.rotation_deg, "random mounting error: rotation up to this (deg)")
      ->capture_default_str();
  cmd->add_option("--jitter-m", a.perturb.translation_m, "random mounting error: translation up to this (m)")
      ->capture_default_str();
  cmd->add_option("--seed", a.perturb.seed, "seed of the mounting error and of the automatic placement")
      ->capture_default_str();
}

// Where the rig stands and how it moves: position and heading, trajectory, automatic placement.
void AddPathOptions(CLI::App* cmd, MakeRigArgs& a) {
  cmd->add_option("--position", a.position, "rig position in the world at frame 0: x,y,z (m, glTF +Y up)")
      ->delimiter(',')
      ->expected(3)
      ->capture_default_str();
  cmd->add_option("--heading", a.heading_deg, "rig heading (deg; 0 = world -Z, 90 = world +X)")
      ->capture_default_str();
  cmd->add_option("--trajectory", a.trajectory, "path over the frames: straight or circle")
      ->capture_default_str()
      ->check(CLI::IsMember({"straight", "circle"}));
  cmd->add_option("--circle-radius", a.circle_radius_m, "circle: radius (m; > 0 turns left, < 0 right)")
      ->capture_default_str();
  cmd->add_option("--frames", a.frames, "number of frames; the rig moves --step along the path between them")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));
  cmd->add_option("--step", a.step_m, "distance moved per frame (m)")->capture_default_str();
  cmd->add_option("--scene", a.scene, "place the rig automatically in this glTF scene")->check(CLI::ExistingFile);
  cmd->add_option("--clearance", a.placement.min_clearance_m, "placement: no surface closer along a camera axis (m)")
      ->capture_default_str();
}

// --from-gltf, which replaces the rig and path options, and where to write.
void AddSourceAndOutputOptions(CLI::App* cmd, MakeRigArgs& a) {
  CLI::Option* from_gltf =
      cmd->add_option("--from-gltf", a.from_gltf,
                      "take the rig from the perspective cameras of this glTF file (see above); rig type, "
                      "camera, placement and trajectory options do not apply")
          ->check(CLI::ExistingFile);
  for (const char* name : {"type", "--cameras", "--spacing", "--overlap", "--hfov", "--radius", "--distorted", "--k1", "--k2",
                           "--lens", "--lens-k1", "--fisheye-fov",
                           "--baseline", "--convergence", "--side-fov", "--vehicle", "--position", "--heading",
                           "--trajectory", "--circle-radius", "--frames", "--step", "--scene", "--clearance"}) {
    from_gltf->excludes(cmd->get_option(name));
  }
  CLI::Option* rig_out = cmd->add_option("--rig-out", a.rig_out, "rig.json to write");
  CLI::Option* frames_out = cmd->add_option("--frames-out", a.frames_out, "frames.json to write");
  cmd->add_option("--out", a.out,
                  "instead of --rig-out and --frames-out: folder to write rig.json and frames.json into (appears "
                  "complete or not at all; see --force)")
      ->excludes(rig_out)
      ->excludes(frames_out);
  cmd->add_flag("--force", a.force, "with --out: replace an existing folder");
}

// Capture timing: when each camera captures relative to the frame, its rolling shutter and exposure.
void AddTimingOptions(CLI::App* cmd, MakeRigArgs& a) {
  const std::string group = "Capture timing (per camera: CAMERA=VALUE; a plain VALUE sets every camera; repeatable)";
  cmd->add_option("--time-offset", a.time_offset,
                  "capture delay after the frame's timestamp (s): the camera sees from where the moving rig is then")
      ->group(group);
  cmd->add_option("--readout", a.readout, "rolling shutter: time to read out all rows (s), 0 = global shutter")->group(group);
  cmd->add_option("--readout-direction", a.readout_direction, "rolling shutter: top-to-bottom (default) or bottom-to-top")
      ->group(group);
  cmd->add_option("--exposure", a.exposure, "exposure time (s): colour samples spread over it (motion blur, needs --spp > 1)")
      ->group(group);
}

// Applies "VALUE" (every camera) then "CAMERA=VALUE" entries of one timing option.
template <class Set>
void ApplyPerCamera(const std::vector<std::string>& entries, const std::string& option, Rig* rig, Set&& set) {
  for (const bool named : {false, true}) {
    for (const std::string& entry : entries) {
      const size_t eq = entry.find('=');
      if ((eq != std::string::npos) != named) continue;
      const std::string value = named ? entry.substr(eq + 1) : entry;
      for (RigCamera& cam : rig->cameras) {
        if (named && cam.name != entry.substr(0, eq)) continue;
        set(cam, value);
      }
      if (named && rig->FindCamera(entry.substr(0, eq)) < 0) {
        throw CLI::ValidationError(option, "no camera named '" + entry.substr(0, eq) + "' in the rig");
      }
    }
  }
}

void ApplyTiming(const MakeRigArgs& a, Rig* rig) {
  auto seconds = [](const std::string& option, const std::string& text, bool signed_ok) {
    size_t used = 0;
    double v = 0;
    try {
      v = std::stod(text, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != text.size() || !std::isfinite(v) || (!signed_ok && v < 0) || std::abs(v) > 3600) {
      throw CLI::ValidationError(option, "'" + text + "' is not a time in seconds" + (signed_ok ? "" : " >= 0"));
    }
    return v;
  };
  ApplyPerCamera(a.time_offset, "--time-offset", rig,
                 [&](RigCamera& c, const std::string& v) { c.time_offset_s = seconds("--time-offset", v, true); });
  ApplyPerCamera(a.readout, "--readout", rig, [&](RigCamera& c, const std::string& v) { c.readout_s = seconds("--readout", v, false); });
  ApplyPerCamera(a.exposure, "--exposure", rig,
                 [&](RigCamera& c, const std::string& v) { c.exposure_s = seconds("--exposure", v, false); });
  ApplyPerCamera(a.readout_direction, "--readout-direction", rig, [&](RigCamera& c, const std::string& v) {
    if (v != "top-to-bottom" && v != "bottom-to-top") {
      throw CLI::ValidationError("--readout-direction", "'" + v + "': use top-to-bottom or bottom-to-top");
    }
    c.readout_bottom_to_top = v == "bottom-to-top";
  });
}

// Where to write, checked before any work.
void CheckOutput(const MakeRigArgs& a) {
  if (a.out.empty() && (a.rig_out.empty() || a.frames_out.empty())) {
    throw CLI::ValidationError("make-rig", "give --out DIR, or both --rig-out FILE and --frames-out FILE");
  }
  if (!a.out.empty() && std::filesystem::exists(a.out) && !a.force) {
    throw std::runtime_error(a.out + ": already exists (use --force to replace it)");
  }
}

// Writes rig.json and frames.json (into --out, complete or not at all, or to --rig-out and
// --frames-out) and says so; `what` names the rig.
void WriteRigAndFrames(const MakeRigArgs& a, const Rig& rig, const FramesFile& frames, const std::string& what) {
  std::string rig_path = a.rig_out, frames_path = a.frames_out;
  if (!a.out.empty()) {
    StagedOutput staged(a.out, a.force);
    WriteRig(rig, staged.staging_dir() / "rig.json");
    WriteFrames(frames, staged.staging_dir() / "frames.json");
    staged.Commit();
    rig_path = (std::filesystem::path(a.out) / "rig.json").string();
    frames_path = (std::filesystem::path(a.out) / "frames.json").string();
  } else {
    WriteRig(rig, rig_path);
    WriteFrames(frames, frames_path);
  }
  std::printf("wrote %s (%s, %zu cameras) and %s (%zu frames, %s)\n", rig_path.c_str(), what.c_str(),
              rig.cameras.size(), frames_path.c_str(), frames.frames.size(),
              a.from_gltf.empty() ? a.trajectory.c_str() : "the file's camera poses");
}

void PerturbIfAsked(const MakeRigArgs& a, Rig* rig) {
  if (a.perturb.rotation_deg > 0 || a.perturb.translation_m > 0) PerturbRig(*rig, a.perturb);
}

// --from-gltf: the file's perspective cameras, where the file puts them.
void MakeRigFromGltf(const MakeRigArgs& a) {
  const Scene scene = LoadSceneVerbose(a.from_gltf);  // its warnings name the cameras it skipped
  SceneCameraRig from_file = RigFromSceneCameras(scene, a.ring.width, a.ring.height);
  for (const std::string& w : from_file.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  PerturbIfAsked(a, &from_file.rig);
  ApplyTiming(a, &from_file.rig);
  for (const RigCamera& c : from_file.rig.cameras) {
    const Eigen::Vector3d centre = (*c.cam_from_rig * *from_file.frames.frames[0].rig_from_world).SourceOriginInTarget();
    std::printf("  %-12s PINHOLE %dx%d  fx %.2f fy %.2f  at (%.3f, %.3f, %.3f)\n", c.name.c_str(), c.camera.width(),
                c.camera.height(), c.camera.fx(), c.camera.fy(), centre.x(), centre.y(), centre.z());
  }
  WriteRigAndFrames(a, from_file.rig, from_file.frames, "from " + std::filesystem::path(a.from_gltf).filename().string());
}

// The rig, its path and its placement as the options give them.
RigSpec SpecOf(const MakeRigArgs& a, const CLI::App& cmd) {
  RigSpec s;
  s.type = a.type;
  s.ring = a.ring;
  // The default distorted camera (index 1) only exists from two cameras on.
  if (cmd.count("--distorted") == 0 && s.ring.distorted_camera >= s.ring.num_cameras) s.ring.distorted_camera = -1;
  s.stereo = a.stereo;
  s.surround = a.surround;
  s.wide = a.wide;
  s.width = a.ring.width;
  s.height = a.ring.height;
  if (cmd.count("--hfov") > 0) s.hfov_deg = a.hfov_deg;
  if (cmd.count("--baseline") > 0) s.baseline_m = a.stereo.baseline_m;
  if (a.lens != "preset") {
    LensOptions lens;
    lens.kind = LensKindFromName(a.lens);
    lens.k1 = a.lens_k1;
    lens.fisheye_fov_deg = a.fisheye_fov_deg;
    s.lens = lens;
  }
  s.overlap_percent = a.overlap_percent;
  s.perturbation = a.perturb;
  s.trajectory.kind = a.trajectory == "circle" ? TrajectoryKind::kCircle : TrajectoryKind::kStraight;
  s.trajectory.start_world = Eigen::Vector3d(a.position[0], a.position[1], a.position[2]);
  s.trajectory.heading_deg = a.heading_deg;
  s.trajectory.num_frames = a.frames;
  s.trajectory.step_m = a.step_m;
  s.trajectory.circle_radius_m = a.circle_radius_m;
  s.placement = a.placement;
  s.placement.height_m = a.position[1] > 0 && cmd.count("--position") ? a.position[1] : s.placement.height_m;
  s.placement.seed = a.perturb.seed;
  return s;
}

void MakeRig(const MakeRigArgs& a, const CLI::App& cmd) {
  CheckOutput(a);
  if (!a.from_gltf.empty()) {
    MakeRigFromGltf(a);
    return;
  }
  const RigSpec spec = SpecOf(a, cmd);
  std::optional<Scene> scene;
  if (!a.scene.empty()) scene = LoadGltf(a.scene);
  std::optional<PlacedRig> placed = MakePlacedRig(spec, scene ? &*scene : nullptr);
  if (!placed) {
    throw std::runtime_error(a.scene + ": no place found where the rig stands on the ground with " +
                             std::to_string(spec.placement.min_clearance_m) +
                             " m clearance; try a smaller --clearance or fewer --frames");
  }
  if (placed->placement) {
    const RigPlacement& p = *placed->placement;
    std::printf("placed at (%.2f, %.2f, %.2f), heading %.1f deg (%.0f%% of probe rays see structure)\n",
                p.position_world.x(), p.position_world.y(), p.position_world.z(), p.heading_deg, 100.0 * p.score);
    placed->frames.scene = std::filesystem::path(a.scene).filename().string();
  }
  ApplyTiming(a, &placed->rig);
  WriteRigAndFrames(a, placed->rig, placed->frames, a.type);
}

}  // namespace

void AddMakeRigCommand(CLI::App& app) {
  auto args = std::make_shared<MakeRigArgs>();
  CLI::App* cmd = app.add_subcommand("make-rig", kDescription);
  AddRigOptions(cmd, *args);
  AddPathOptions(cmd, *args);
  AddSourceAndOutputOptions(cmd, *args);
  AddTimingOptions(cmd, *args);
  cmd->callback([args, cmd] { MakeRig(*args, *cmd); });
}

}  // namespace rigsim::cli
