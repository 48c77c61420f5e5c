#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "apps/rigsim/commands.h"
#include "apps/rigsim/render_support.h"
#include "common/did_you_mean.h"
#include "common/format.h"
#include "dataset/dataset.h"
#include "dataset/output_file.h"
#include "dataset/output_folder.h"
#include "geometry/rig.h"
#include "gltf/gltf_loader.h"
#include "gltf/label_rules.h"
#include "gltf/scene_cameras.h"
#include "procedural/ego_vehicle.h"
#include "rigs/rig_params.h"
#include "rigs/rig_spec.h"

namespace rigsim::cli {
namespace {

// What make-rig's options set: the rig's parameters (rigs/rig_params.h) as typed, and make-rig's own.
struct MakeRigArgs {
  std::map<std::string, std::string> rig_text;         // parameter name -> the text given
  std::map<std::string, CLI::Option*> rig_options;     // parameter name -> its option
  std::vector<double> position = {0.0, 1.6, 0.0};
  uint64_t seed = 1;
  std::string scene;
  std::string rules;  // label rules for --scene
  std::string from_gltf;
  std::string rig_out, frames_out, out;
  bool force = false;
  bool ego_vehicle = false;
  bool rig_position_given = false;  // --position, after parsing
  // Capture timing: "SECONDS" for every camera or "CAMERA=SECONDS" for one (repeatable).
  std::vector<std::string> time_offset, readout, readout_direction, exposure;

  // The rig parameters given, checked (each option's check already passed).
  nlohmann::ordered_json RigValues() const {
    nlohmann::ordered_json values = nlohmann::ordered_json::object();
    for (const RigParam& p : RigParams()) {
      if (rig_options.at(p.spec.name)->count() > 0) values[p.spec.name] = ParamValueFromText(p.spec, rig_text.at(p.spec.name));
    }
    return values;
  }
};

constexpr const char* kDescription =
    "Write a rig (rig.json) and its placement in a scene over K frames (frames.json) for `rigsim render`.\n"
    "Types:\n"
    "  ring           cam0..camN-1 on a horizontal circle facing outwards, left to right (--spacing or --overlap)\n"
    "  stereo         left/right, parallel, --baseline apart\n"
    "  surround       vehicle-like: front (OPENCV), right and left (OPENCV_FISHEYE, --side-fov > 180 ok), back (PINHOLE)\n"
    "  wide-baseline  cam0/cam1 --baseline apart, toed in by --convergence in total\n"
    "  file           the cameras of --rig-file, to put your own rig on a path: a rig.json as make-rig writes\n"
    "                 it (intrinsics and cam_from_rig), a Kalibr camchain.yaml, a COLMAP 3.12 text model with\n"
    "                 rigs.txt and cameras.txt (its folder or either file; or a rig_config.json beside the\n"
    "                 model's cameras.txt and images.txt), a DGP/DDAD calibration JSON (image sizes from the\n"
    "                 scene_*.json above calibration/) or nuScenes calibrated_sensor.json (channels and image\n"
    "                 sizes from sensor.json and sample_data.json beside it). The rig frame is the first\n"
    "                 camera's (nuScenes: CAM_FRONT); docs/scenes-and-rigs.md has each format's conventions\n"
    "Paths (--trajectory), and what each fixes of every camera's place in the rig from its own motion:\n"
    "  straight       --step per frame: fixes nothing where cameras do not overlap\n"
    "  circle         an arc of --circle-radius, --step per frame: turns about one axis, so each camera's\n"
    "                 height stays open\n"
    "  loop           one whole lap of the circle over the frames, back to the start (planar as circle)\n"
    "  figure-eight   a lap turning left, then one turning right (planar as circle)\n"
    "  handheld       the arc, pitching and rolling by up to --tilt: turns about three axes, which fixes\n"
    "                 every camera's place (a handheld or drone rig)\n"
    "With --scene the rig is placed automatically on the ground where every camera sees structure\n"
    "and no surface is closer than --clearance (overrides --position and --heading), where its whole\n"
    "path stays on the ground and out of the scene's geometry, its origin --rig-height above the ground.\n"
    "--placement road places a vehicle rig as a car drives instead: on the surface labelled road\n"
    "(Cityscapes 'road', from the scene's extras.class or a --rules file), heading along the road's long\n"
    "direction (the way the road continues furthest), in the right-hand lane (a quarter of the road's width\n"
    "right of its centre line) where the road is wide enough for two lanes (5.5 m), else on the centre\n"
    "line; the whole path keeps the rig's 2 m wide footprint on the road and out of the geometry, and\n"
    "--clearance is kept along the lane ahead. An imported rig's frame is its first camera's, so that\n"
    "camera stands --rig-height (1.6 m) above the road.\n"
    "With --from-gltf SCENE the rig is the perspective cameras that SCENE places on its nodes instead\n"
    "(PINHOLE, --width x --height, field of view from each camera's yfov and aspectRatio; cam_from_rig\n"
    "relative to the first camera in file order) and frames.json holds one frame with the rig where the\n"
    "file puts it, so `rigsim render` reproduces the file's views.\n"
    "Output: --rig-out and --frames-out, or --out DIR for DIR/rig.json and DIR/frames.json.\n"
    "With --ego-vehicle (needs --out) the rig gets its own car: DIR/ego_vehicle.glb, named in rig.json, a\n"
    "low-poly body sized from where the cameras are, every camera on its skin (roof 5 cm below the lowest\n"
    "camera and 10 cm beyond the outermost every way, levelled to the cameras; windshield, bonnet and boot\n"
    "beyond it, a car's size at least, down to 0.2 m above the ground), labelled `ego vehicle`, with glossy\n"
    "paint and glass that reflect the world. `rigsim render` moves it with the rig at every camera's capture\n"
    "time (rolling shutter and time offsets included): it shows in the lower part of views that look out and\n"
    "down past the roof, as a real car's body does.";

// A parameter's check as an option's validator: the refusal reads as the sweep's does.
CLI::Validator CheckOf(const ParamSpec& spec) {
  std::string description;
  if (spec.kind == ParamSpec::Kind::kChoice) {
    for (const std::string& c : spec.choices) description += (description.empty() ? "{" : ",") + c;
    description += "}";
  } else if (spec.kind == ParamSpec::Kind::kInt || spec.kind == ParamSpec::Kind::kNumber) {
    description = "in [" + FormatParamValue(spec.min) + " - " + FormatParamValue(spec.max) + "]";
  }
  return CLI::Validator(
      [spec](std::string& text) -> std::string {
        try {
          ParamValueFromText(spec, text);
          return "";
        } catch (const std::invalid_argument& e) {
          return e.what();
        }
      },
      description);
}

// The rig and its path: an option for every rig parameter, then where the rig stands without a scene.
void AddRigOptions(CLI::App* cmd, MakeRigArgs& a) {
  for (const RigParam& p : RigParams()) {
    CLI::Option* option = cmd->add_option(p.Flags(), a.rig_text[p.spec.name], p.spec.help)
                              ->check(CheckOf(p.spec))
                              ->type_name(p.spec.kind == ParamSpec::Kind::kInt      ? "INT"
                                          : p.spec.kind == ParamSpec::Kind::kNumber ? "FLOAT"
                                                                                    : "TEXT");
    if (!p.spec.default_value.is_null()) option->default_str(FormatParamValue(p.spec.default_value));
    a.rig_options[p.spec.name] = option;
  }
  cmd->add_option("--position", a.position, "rig position in the world at frame 0 without a scene: x,y,z (m, glTF +Y up)")
      ->delimiter(',')
      ->expected(3)
      ->capture_default_str();
  cmd->add_option("--seed", a.seed, "seed of the mounting error, the lens residual and the automatic placement")->capture_default_str();
  cmd->add_option("--scene", a.scene,
                  "place the rig automatically in this glTF scene: on the ground where every camera sees structure "
                  "(overrides --position and --heading)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--rules", a.rules,
                  "label rules JSON for --scene: classes from node, mesh or material names (a glTF without "
                  "extras.class), e.g. which surfaces are road for --placement road")
      ->check(CLI::ExistingFile)
      ->needs(cmd->get_option("--scene"));
}

// --from-gltf, which replaces the rig and path options, and where to write.
void AddSourceAndOutputOptions(CLI::App* cmd, MakeRigArgs& a) {
  CLI::Option* from_gltf =
      cmd->add_option("--from-gltf", a.from_gltf,
                      "take the rig from the perspective cameras of this glTF file (see above); rig type, "
                      "camera, placement and trajectory options do not apply")
          ->check(CLI::ExistingFile);
  // The image size and mounting errors apply to the file's cameras too.
  for (const RigParam& p : RigParams()) {
    if (p.group == RigParamGroup::kRig || p.group == RigParamGroup::kPath) from_gltf->excludes(a.rig_options.at(p.spec.name));
  }
  for (const char* name : {"--position", "--scene"}) from_gltf->excludes(cmd->get_option(name));
  CLI::Option* rig_out = cmd->add_option("--rig-out", a.rig_out, "rig.json to write");
  CLI::Option* frames_out = cmd->add_option("--frames-out", a.frames_out, "frames.json to write");
  cmd->add_option("--out", a.out,
                  "instead of --rig-out and --frames-out: folder to write rig.json and frames.json into (appears "
                  "complete or not at all; see --force)")
      ->excludes(rig_out)
      ->excludes(frames_out);
  cmd->add_flag("--ego-vehicle", a.ego_vehicle,
                "attach a car body around the rig (DIR/ego_vehicle.glb, labelled 'ego vehicle', glossy paint): "
                "render shows it in every view that sees it; needs --out");
  cmd->add_flag("--force", a.force, "replace an existing --out folder rigsim wrote, or existing --rig-out and --frames-out JSON files");
}

// What make-rig reads, which none of its outputs may replace.
std::vector<CommandInput> Inputs(const MakeRigArgs& a) {
  std::vector<CommandInput> inputs;
  if (!a.scene.empty()) inputs.push_back({a.scene, "--scene"});
  if (!a.rules.empty()) inputs.push_back({a.rules, "--rules"});
  if (!a.from_gltf.empty()) inputs.push_back({a.from_gltf, "--from-gltf"});
  if (const std::string& rig_file = a.rig_text.at("rig_file"); !rig_file.empty()) inputs.push_back({rig_file, "--rig-file"});
  return inputs;
}

// --out DIR.
OutputFolderRequest OutputFolder(const MakeRigArgs& a) { return {a.out, "--out", "rigsim make-rig", Inputs(a), a.force}; }

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
  // Two plain values would silently keep the last one: a list of values is not read in camera order.
  if (std::count_if(entries.begin(), entries.end(), [](const std::string& e) { return e.find('=') == std::string::npos; }) > 1) {
    throw CLI::ValidationError(option, "give one plain VALUE (every camera) or CAMERA=VALUE per camera, e.g. " + option +
                                           " cam1=0.03 cam2=0.06; several plain values are not read in camera order");
  }
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
        std::vector<std::string> names;
        std::string list;
        for (const RigCamera& c : rig->cameras) {
          names.push_back(c.name);
          list += (list.empty() ? "" : ", ") + c.name;
        }
        throw CLI::ValidationError(option, "no camera named '" + entry.substr(0, eq) + "' in the rig" +
                                               DidYouMean(entry.substr(0, eq), names) + "; its cameras are " + list);
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
  if (a.ego_vehicle && a.out.empty()) {
    throw CLI::ValidationError("make-rig", "--ego-vehicle writes ego_vehicle.glb beside rig.json: give --out DIR "
                                           "instead of --rig-out and --frames-out");
  }
  if (!a.out.empty()) {
    CheckReplaceableOutput(OutputFolder(a));
    return;
  }
  CheckDistinctOutputs({{"--rig-out", a.rig_out}, {"--frames-out", a.frames_out}});
  CheckReplaceableFile({a.rig_out, "--rig-out", OutputFileKind::kJson, Inputs(a), a.force});
  CheckReplaceableFile({a.frames_out, "--frames-out", OutputFileKind::kJson, Inputs(a), a.force});
}

// Writes rig.json and frames.json (into --out, complete or not at all, or to --rig-out and
// --frames-out) and says so; `what` names the rig and `path` its path.
void WriteRigAndFrames(const MakeRigArgs& a, const Rig& rig_in, const FramesFile& frames, const std::string& what,
                       const std::string& path, double ground_below_rig_m) {
  std::string rig_path = a.rig_out, frames_path = a.frames_out;
  Rig rig = rig_in;
  std::vector<uint8_t> ego_vehicle;
  if (a.ego_vehicle) {  // before anything is written: a camera that looks into the body is refused
    try {
      ego_vehicle = EgoVehicleGlb(rig, ground_below_rig_m);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string("--ego-vehicle: ") + e.what());
    }
    rig.ego_vehicle = kEgoVehicleFile;
  }
  if (!a.out.empty()) {
    StagedOutput staged(OutputFolder(a));
    if (a.ego_vehicle) {
      const std::filesystem::path glb = staged.staging_dir() / kEgoVehicleFile;
      std::ofstream file(glb, std::ios::binary);
      file.write(reinterpret_cast<const char*>(ego_vehicle.data()), std::streamsize(ego_vehicle.size()));
      if (!file.flush()) throw std::runtime_error(glb.string() + ": cannot write");
    }
    WriteRig(rig, staged.staging_dir() / "rig.json");
    WriteFrames(frames, staged.staging_dir() / "frames.json");
    staged.Commit();
    rig_path = (std::filesystem::path(a.out) / "rig.json").string();
    frames_path = (std::filesystem::path(a.out) / "frames.json").string();
  } else {
    WriteRig(rig, rig_path);
    WriteFrames(frames, frames_path);
  }
  std::printf("wrote %s (%s, %s) and %s (%s, %s)\n", rig_path.c_str(), what.c_str(), Count(rig.cameras.size(), "camera").c_str(),
              frames_path.c_str(), Count(frames.frames.size(), "frame").c_str(), path.c_str());
  if (a.ego_vehicle) std::printf("wrote %s (the rig's own vehicle)\n", (std::filesystem::path(a.out) / kEgoVehicleFile).string().c_str());
}

// The rig, its path and its placement as the options give them.
RigSpec SpecOf(const MakeRigArgs& a) {
  RigSpec s = RigSpecFromParams(a.RigValues());
  s.perturbation.seed = a.seed;
  s.lens_residual.seed = a.seed;
  s.trajectory.start_world = Eigen::Vector3d(a.position[0], a.position[1], a.position[2]);
  // Without --rig-height, --position's height serves as the rig's height above the ground in a scene.
  if (a.position[1] > 0 && a.rig_position_given && a.rig_options.at("rig_height")->count() == 0) {
    s.placement.height_m = a.position[1];
  }
  s.placement.seed = a.seed;
  return s;
}

// --from-gltf: the file's perspective cameras, where the file puts them.
void MakeRigFromGltf(const MakeRigArgs& a) {
  const RigSpec spec = SpecOf(a);
  const Scene scene = LoadSceneVerbose(a.from_gltf);  // its warnings name the cameras it skipped
  SceneCameraRig from_file = RigFromSceneCameras(scene, spec.width, spec.height);
  for (const std::string& w : from_file.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  if (spec.perturbation.rotation_deg > 0 || spec.perturbation.translation_m > 0) PerturbRig(from_file.rig, spec.perturbation);
  ApplyTiming(a, &from_file.rig);
  for (const RigCamera& c : from_file.rig.cameras) {
    const Eigen::Vector3d centre = (*c.cam_from_rig * *from_file.frames.frames[0].rig_from_world).SourceOriginInTarget();
    std::printf("  %-12s PINHOLE %dx%d  fx %.2f fy %.2f  at (%.3f, %.3f, %.3f)\n", c.name.c_str(), c.camera.width(),
                c.camera.height(), c.camera.fx(), c.camera.fy(), centre.x(), centre.y(), centre.z());
  }
  WriteRigAndFrames(a, from_file.rig, from_file.frames, "from " + std::filesystem::path(a.from_gltf).filename().string(),
                    "the file's camera poses", spec.placement.height_m);
}

// What the rig will see: the overlap of each pair that shares a view at the first frame, and a
// warning when a neighbour pair misses the --overlap asked for.
void ReportOverlaps(const RigSpec& spec, const PlacedRig& placed, const Scene* scene) {
  if (placed.rig.cameras.size() < 2 || !placed.rig.HasAllPoses()) return;
  const std::vector<PairOverlap> pairs = RigPairOverlaps(placed.rig, scene, *placed.frames.frames[0].rig_from_world);
  std::printf("%s\n", scene ? "overlap predicted at the first frame (the smaller of the two directions, the figure render "
                              "and calibrate report from overlap.json):"
                            : "angular overlap for points at infinity (the smaller of the two directions; render measures "
                              "the ground truth, without sky and with parallax: --scene solves for that):");
  std::string line, missed;
  int shown = 0;
  for (const PairOverlap& p : pairs) {
    if (p.overlap < 0.005) continue;
    char text[96];
    std::snprintf(text, sizeof(text), "  %s-%s %5.1f%%", p.a.c_str(), p.b.c_str(), 100 * p.overlap);
    line += text;
    if (++shown % 4 == 0) line += "\n";
    // Neighbours on the ring (camera i and i+1) are what --overlap solves for, pair by pair in a scene.
    const bool neighbours = placed.rig.FindCamera(p.b) == placed.rig.FindCamera(p.a) + 1;
    if (scene && spec.overlap_percent && neighbours && std::abs(100 * p.overlap - *spec.overlap_percent) > 2.0) {
      missed += (missed.empty() ? "" : ", ") + p.a + "-" + p.b;
    }
  }
  if (shown < int(pairs.size())) line += shown % 4 == 0 ? "  (the other pairs 0%)" : "    (the other pairs 0%)";
  if (shown == 0) line = "  every pair 0%";
  std::printf("%s\n", line.c_str());
  if (!missed.empty()) {
    std::fprintf(stderr, "warning: %s: more than 2 points from the --overlap %g%% asked for: no spacing gives it at this "
                 "place (near walls or open sky); try another --seed\n", missed.c_str(), *spec.overlap_percent);
  }
}

void MakeRig(const MakeRigArgs& a) {
  CheckOutput(a);
  if (!a.from_gltf.empty()) {
    MakeRigFromGltf(a);
    return;
  }
  const RigSpec spec = SpecOf(a);
  for (const char* name : {"placement", "rig_height"}) {
    if (a.scene.empty() && a.rig_options.at(name)->count() > 0) {
      throw CLI::ValidationError(a.rig_options.at(name)->get_name(), "applies to placement in a scene: give --scene too "
                                                                     "(without a scene the rig stands at --position)");
    }
  }
  std::optional<Scene> scene;
  if (!a.scene.empty()) {
    std::optional<LabelRules> rules;
    GltfLoadOptions options;
    if (!a.rules.empty()) {
      rules = LabelRules::Read(a.rules);
      options.label_rules = &*rules;
    }
    scene = LoadGltf(a.scene, options);
  }
  if (scene && scene->NumTriangles() == 0) {
    throw std::runtime_error(a.scene + ": the scene holds no triangles: there is no ground to place the rig on; give a "
                             "scene with geometry, or leave out --scene and place the rig with --position and --heading");
  }
  std::optional<PlacedRig> placed;
  try {
    placed = MakePlacedRig(spec, scene ? &*scene : nullptr);
  } catch (const NoRoadError& e) {
    throw std::runtime_error(a.scene + ": " + e.what() + "; label the road's surface (extras.class \"road\" on its "
                             "node, mesh or material, or a --rules file by their names), or leave out --placement road");
  }
  if (!placed) throw std::runtime_error(NoPlaceMessage(spec, a.scene));
  if (placed->placement && placed->placement->road) {
    const RigPlacement& p = *placed->placement;
    const RoadSpot& r = *p.road;
    const std::string lane = r.lane_offset_m > 0
                                 ? "in the right-hand lane, " + Fixed(r.lane_offset_m, 1) + " m right of its centre line"
                                 : "on its centre line (too narrow for two lanes)";
    std::printf("placed on the road at (%.2f, %.2f, %.2f), heading %.1f deg along it: road %.1f m wide, %s, clear road "
                "%.0f m ahead and %.0f m behind\n",
                p.position_world.x(), p.position_world.y(), p.position_world.z(), p.heading_deg, r.width_m, lane.c_str(),
                r.clear_ahead_m, r.clear_behind_m);
    placed->frames.scene = std::filesystem::path(a.scene).filename().string();
  } else if (placed->placement) {
    const RigPlacement& p = *placed->placement;
    std::printf("placed at (%.2f, %.2f, %.2f), heading %.1f deg (%.0f%% of probe rays see structure)\n",
                p.position_world.x(), p.position_world.y(), p.position_world.z(), p.heading_deg, 100.0 * p.score);
    if (p.score < 0.1) {
      std::fprintf(stderr, "warning: %s: at the best place found, %.0f%% of the probe rays see structure within %.0f m: the "
                   "views will be mostly empty sky; try another --seed, or a scene with structure around the ground\n",
                   a.scene.c_str(), 100.0 * p.score, spec.placement.max_range_m);
    }
    placed->frames.scene = std::filesystem::path(a.scene).filename().string();
  }
  ApplyTiming(a, &placed->rig);
  ReportOverlaps(spec, *placed, scene ? &*scene : nullptr);
  WriteRigAndFrames(a, placed->rig, placed->frames, std::string(RigTypeName(spec.type)),
                    std::string(TrajectoryKindName(spec.trajectory.kind)), spec.placement.height_m);
}

}  // namespace

void AddMakeRigCommand(CLI::App& app) {
  auto args = std::make_shared<MakeRigArgs>();
  CLI::App* cmd = app.add_subcommand("make-rig", kDescription);
  AddRigOptions(cmd, *args);
  AddSourceAndOutputOptions(cmd, *args);
  AddTimingOptions(cmd, *args);
  cmd->callback([args, cmd] {
    args->rig_position_given = cmd->count("--position") > 0;
    MakeRig(*args);
  });
}

}  // namespace rigsim::cli
