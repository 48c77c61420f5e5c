#include <chrono>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "apps/rigsim/commands.h"
#include "apps/rigsim/progress.h"
#include "apps/rigsim/render_support.h"
#include "apps/rigsim/shard_options.h"
#include "apps/rigsim/version.h"
#include "common/format.h"
#include "dataset/capture_poses.h"
#include "dataset/output_folder.h"
#include "dataset/render_shards.h"
#include "geometry/camera_validation.h"
#include "geometry/rig.h"
#include "gltf/gltf_loader.h"
#include "procedural/ego_vehicle.h"
#include "renderer/render_dataset.h"

namespace rigsim::cli {

namespace {

namespace fs = std::filesystem;

std::string Absolute(const std::string& path) { return fs::absolute(path).lexically_normal().string(); }

}  // namespace

void AddRenderCommand(CLI::App& app) {
  struct Args {
    std::string scene, rules, rig, frames, out;
    RenderSettings settings;
    PhotometricSettings photometric;
    SensorSettings sensor;
    bool force = false;
    ExtraOutputs extras;
    ShardSettings shards;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "render",
      "Render a dataset: every camera of RIG at every frame of FRAMES, with labels, instances, depth,\n"
      "the rig and frames files and the ground-truth overlap (see docs/datasets.md).");
  cmd->add_option("--scene", args->scene, "glTF 2.0 scene (.gltf or .glb)")->required()->check(CLI::ExistingFile);
  AddLabelRulesOption(*cmd, args->rules);
  cmd->add_option("--rig", args->rig, "rig.json with every camera's cam_from_rig (rigsim make-rig writes one)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--frames", args->frames, "frames.json with every frame's rig_from_world")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--out", args->out, "output dataset folder (created; see --force)")->required();
  cmd->add_flag("--force", args->force, "replace an existing output folder");
  AddRenderSettingsOptions(*cmd, args->settings);
  AddSensorOptions(*cmd, args->sensor);
  AddPhotometricOptions(*cmd, args->photometric);
  const std::string group = "More ground truth (off unless asked for; docs/datasets.md)";
  cmd->add_flag("--correspondence", args->extras.correspondence,
                "correspondence/<a>/<b>/<frame>.exr for every camera pair that shares a view, flow/<cam>/<frame>.exr to "
                "the next frame: where each pixel's surface lands in the other image (x, y) and whether it is visible there")
      ->group(group);
  cmd->add_flag("--normals", args->extras.normals, "normals/<cam>/<frame>.exr: surface normals in the camera frame")->group(group);
  cmd->add_flag("--coco", args->extras.coco, "instances_coco.json: instance boxes and masks in the COCO format")->group(group);
  cmd->add_flag("--previews", args->extras.previews, "depth_color/ and instances_color/ PNGs to look at")->group(group);
  AddShardOptions(*cmd, args->shards, "frames", "render-merge");
  cmd->callback([args] {
    // The output folder and the small inputs first, so that their errors come before the scene's
    // loading time.
    OutputFolderRequest out{args->out, "--out", "rigsim render", {}, args->force};
    out.inputs = {{args->scene, "--scene"}, {args->rig, "--rig"}, {args->frames, "--frames"}};
    if (!args->rules.empty()) out.inputs.push_back({args->rules, "--rules"});
    CheckReplaceableOutput(out);
    RenderJob job;
    job.options = args->settings.ToRenderOptions();
    job.extras = args->extras;
    ApplySensorSettings(args->sensor, args->photometric, args->settings.seed, job);
    job.rig = ReadRig(args->rig);
    for (const std::string& w : CheckRigCoversImages(job.rig, args->rig)) std::fprintf(stderr, "warning: %s\n", w.c_str());
    job.frames = ReadFrames(args->frames);
    RequirePoses(job.rig, args->rig, job.frames, args->frames, "render");
    CapturePoses(job.rig.cameras, job.frames, args->frames);  // a timed camera needs distinct timestamps
    const Scene scene = LoadSceneVerbose(args->scene, args->rules);
    if (scene.NumTriangles() == 0) {
      std::fprintf(stderr, "warning: %s: the scene holds no triangles: every view will be empty sky\n", args->scene.c_str());
    }
    job.scene = &scene;
    // The rig's own vehicle (make-rig --ego-vehicle), beside rig.json, in the rig frame.
    std::optional<Scene> ego_vehicle;
    if (!job.rig.ego_vehicle.empty()) {
      const fs::path path = fs::path(args->rig).parent_path() / job.rig.ego_vehicle;
      if (!fs::is_regular_file(path)) {
        throw std::runtime_error(args->rig + ": ego_vehicle '" + job.rig.ego_vehicle + "': no such file beside it (" +
                                 path.string() + "); make-rig --ego-vehicle writes it with rig.json");
      }
      ego_vehicle = LoadSceneVerbose(path);
      EgoVehicleToRigFrame(*ego_vehicle);
      job.ego_vehicle = &*ego_vehicle;
      job.rig.ego_vehicle.clear();  // the dataset's rig.json names no file the dataset does not hold
    }
    job.scene_name = std::filesystem::path(args->scene).filename().string();
    job.frames.label_rules = args->rules.empty() ? "" : std::filesystem::path(args->rules).filename().string();
    job.frames.tool_version = RIGSIM_VERSION_STRING;
    const int num_frames = int(job.frames.frames.size());
    if (args->shards.slurm) {
      if (!args->shards.shard.empty()) throw std::invalid_argument("--slurm makes the shards itself: leave out --shard");
      SlurmArrayJob slurm = args->shards.job;
      slurm.binary = fs::read_symlink("/proc/self/exe");
      slurm.command = "render";
      slurm.args = {"--scene", Absolute(args->scene), "--rig", Absolute(args->rig), "--frames", Absolute(args->frames),
                    "--spp", std::to_string(args->settings.samples_per_pixel), "--seed", std::to_string(args->settings.seed)};
      if (!args->rules.empty()) slurm.args.insert(slurm.args.end(), {"--rules", Absolute(args->rules)});
      for (const std::string& a : SensorArgs(args->sensor, args->photometric)) slurm.args.push_back(a);
      for (const auto& [flag, on] : {std::pair{"--correspondence", args->extras.correspondence}, {"--normals", args->extras.normals},
                                     {"--coco", args->extras.coco}, {"--previews", args->extras.previews}}) {
        if (on) slurm.args.push_back(flag);
      }
      slurm.merge_command = "render-merge";
      slurm.out = Absolute(args->out);
      slurm.work = slurm.out.string() + ".shards";
      slurm.name = slurm.out.filename().string();
      if (fs::exists(slurm.out)) {
        throw std::invalid_argument("--out " + args->out + ": already exists; the merge job writes the dataset there, so give a new folder");
      }
      if (fs::exists(slurm.work)) {
        throw std::invalid_argument(slurm.work.string() + ": already exists (the shards of an earlier --slurm render?); remove it or give another --out");
      }
      if (slurm.num_shards <= 0) slurm.num_shards = std::min(64, num_frames);
      if (slurm.num_shards > num_frames) {
        throw std::invalid_argument("--shards " + std::to_string(slurm.num_shards) + ": " + args->frames + " has " +
                                    Count(num_frames, "frame") + "; use at most that many shards");
      }
      SubmitOrWriteSlurm(slurm, args->shards.dry_run);
      return;
    }
    if (!args->shards.shard.empty()) {
      std::tie(job.shard.index, job.shard.count) = ParseShard(args->shards.shard);
      if (job.shard.count > num_frames) {
        throw std::invalid_argument("--shard " + args->shards.shard + ": " + args->frames + " has " +
                                    Count(num_frames, "frame") + "; split it into at most " + Count(num_frames, "shard"));
      }
    }
    RenderAndReport(job, args->out, args->force);
  });
}

void AddRenderMergeCommand(CLI::App& app) {
  struct Args {
    std::string out;
    std::vector<std::string> shards;
    bool force = false;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "render-merge",
      "Combine the folders of a render's shards (rigsim render ... --shard I/N) into one dataset OUT,\n"
      "byte for byte what rendering every frame on one machine writes. Refuses folders of another render\n"
      "and names the shards that are missing; writes nothing unless every shard is there.");
  cmd->add_option("OUT", args->out, "the dataset folder to write (created; see --force)")->required();
  cmd->add_option("SHARD_DIR", args->shards, "the shards' folders, in any order")->required()->check(CLI::ExistingDirectory);
  cmd->add_flag("--force", args->force, "replace OUT when rigsim wrote it");
  cmd->callback([args] {
    const std::vector<fs::path> shards(args->shards.begin(), args->shards.end());
    MergeRenderShards(args->out, shards, args->force);
    const FramesFile frames = ReadFrames(DatasetLayout(args->out).FramesJson());
    std::printf("merged %s (%s) into %s\n", Count(shards.size(), "shard").c_str(), Count(frames.frames.size(), "frame").c_str(),
                args->out.c_str());
  });
}

}  // namespace rigsim::cli
