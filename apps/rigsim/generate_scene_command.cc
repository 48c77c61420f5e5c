// rigsim generate-scene --preset street|plaza|parking --seed S --out FILE.glb [--animated [--traffic N]]
#include <cstdio>
#include <filesystem>
#include <string>

#include "apps/rigsim/commands.h"
#include "common/param_spec.h"
#include "dataset/output_file.h"
#include "procedural/presets.h"

namespace rigsim::cli {

void AddGenerateSceneCommand(CLI::App& app) {
  struct Args {
    std::string preset = "street";
    uint64_t seed = 1;
    bool animated = false;
    double traffic = kDefaultTraffic;
    bool force = false;
    std::string out;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "generate-scene",
      "Write a seeded procedural world as a labelled .glb (class extras per node, one instance per node):\n"
      "  street   street canyon: repetitive facades, parked cars (assets/scenes/street.glb is seed 1)\n"
      "  plaza    open square: distant buildings, much sky and vegetation (alpha-masked foliage), people\n"
      "  parking  parking lot: ground-dominated views, rows of identical car models\n"
      "Every preset puts the same poster on a wall and on a bus (a semantic distractor).");
  cmd->add_option("--preset", args->preset, "the world to generate (above)")
      ->capture_default_str()
      ->check(CLI::IsMember(NamesOf(AllScenePresets(), ScenePresetName)));
  cmd->add_option("--seed", args->seed, "random seed; the same seed gives the same bytes")->capture_default_str();
  CLI::Option* animated = cmd->add_flag(
      "--animated", args->animated,
      "the world moves for 60 s (glTF LINEAR translation and rotation channels; the static scene is unchanged): "
      "people walk back and forth with a gait, cars drive their lanes (--traffic), buses drive to their stop, "
      "trees sway in the wind. The sky is not geometry and does not move");
  cmd->add_option("--traffic", args->traffic,
                  "with --animated: moving cars per 100 m of lane (0 = no vehicle moves; the street has 240 m of lane, "
                  "the parking 120 m, the plaza none: its bus drives when this is above 0); cars beyond the scene's "
                  "lane cars are added")
      ->capture_default_str()
      ->check(CLI::Range(0.0, kMaxTraffic))
      ->needs(animated);
  cmd->add_option("--out", args->out, "output .glb")->required();
  cmd->add_flag("--force", args->force, "replace an existing .glb file");
  cmd->callback([args] {
    const std::filesystem::path out(args->out);
    CheckReplaceableFile({out, "--out", OutputFileKind::kGlb, {}, args->force});
    // Written next to the target and renamed into place, so a failure leaves no half file.
    const std::filesystem::path tmp = out.string() + ".tmp";
    ScenePresetOptions o;
    o.preset = ScenePresetFromName(args->preset);
    o.seed = args->seed;
    o.animated = args->animated;
    o.traffic = args->traffic;
    try {
      WriteScenePreset(o, tmp);
    } catch (...) {
      std::filesystem::remove(tmp);
      throw;
    }
    std::error_code ec;
    std::filesystem::rename(tmp, out, ec);
    if (ec) {
      std::filesystem::remove(tmp);
      throw std::runtime_error(out.string() + ": cannot move the written scene into place: " + ec.message());
    }
    char motion[64] = "";
    if (args->animated) std::snprintf(motion, sizeof motion, ", animated, traffic %g", args->traffic);
    std::printf("wrote %s (%s, seed %llu%s, %.1f MB); check it with `rigsim inspect %s`\n", out.string().c_str(),
                args->preset.c_str(), static_cast<unsigned long long>(args->seed), motion,
                std::filesystem::file_size(out) / 1e6, out.string().c_str());
  });
}

}  // namespace rigsim::cli
