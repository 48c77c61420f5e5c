#include <chrono>
#include <cstdio>

#include "apps/rigsim/commands.h"
#include "apps/rigsim/progress.h"
#include "apps/rigsim/render_support.h"
#include "apps/rigsim/version.h"
#include "dataset/output_folder.h"
#include "geometry/camera_validation.h"
#include "geometry/rig.h"
#include "gltf/gltf_loader.h"
#include "renderer/render_dataset.h"

namespace rigsim::cli {

void AddRenderCommand(CLI::App& app) {
  struct Args {
    std::string scene, rules, rig, frames, out;
    RenderSettings settings;
    PhotometricSettings photometric;
    bool force = false;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "render",
      "Render a dataset: every camera of RIG at every frame of FRAMES, with labels, instances, depth,\n"
      "the rig and frames files and the ground-truth overlap (see README, 'Dataset layout').");
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
  AddPhotometricOptions(*cmd, args->photometric);
  cmd->callback([args] {
    // The output folder and the small inputs first, so that their errors come before the scene's
    // loading time.
    OutputFolderRequest out{args->out, "--out", "rigsim render", {}, args->force};
    out.inputs = {{args->scene, "--scene"}, {args->rig, "--rig"}, {args->frames, "--frames"}};
    if (!args->rules.empty()) out.inputs.push_back({args->rules, "--rules"});
    CheckReplaceableOutput(out);
    RenderJob job;
    job.options = args->settings.ToRenderOptions();
    job.photometric = args->photometric.ToOptions(args->settings.seed);
    job.rig = ReadRig(args->rig);
    for (const std::string& w : CheckRigCoversImages(job.rig, args->rig)) std::fprintf(stderr, "warning: %s\n", w.c_str());
    job.frames = ReadFrames(args->frames);
    RequirePoses(job.rig, args->rig, job.frames, args->frames, "render");
    const Scene scene = LoadSceneVerbose(args->scene, args->rules);
    if (scene.NumTriangles() == 0) {
      std::fprintf(stderr, "warning: %s: the scene holds no triangles: every view will be empty sky\n", args->scene.c_str());
    }
    job.scene = &scene;
    job.scene_name = std::filesystem::path(args->scene).filename().string();
    job.frames.label_rules = args->rules.empty() ? "" : std::filesystem::path(args->rules).filename().string();
    job.frames.tool_version = RIGSIM_VERSION_STRING;
    RenderAndReport(job, args->out, args->force);
  });
}

}  // namespace rigsim::cli
