// rigsim generate-scene --preset street|plaza|parking --seed S --out FILE.glb [--animated [--traffic N]] [--glass] [--wet F]
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
    bool glass = false;
    double wet = 0.0;
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
  cmd->add_flag("--glass", args->glass,
                "the facades' windows and shop windows are glass (smooth, dark, labelled building) that mirrors the "
                "street in render's one specular bounce; the rest of the world is unchanged");
  cmd->add_option("--wet", args->wet,
                  "puddles (smooth water over darkened asphalt, labelled as the road they lie on) cover about this share "
                  "of the road: the street's road and the parking's asphalt; the plaza has none. They mirror the world "
                  "above them; the rest of the world is unchanged. 0 = dry")
      ->capture_default_str()
      ->check(CLI::Range(0.0, kMaxWet));
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
    o.glass = args->glass;
    o.wet = args->wet;
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
    char motion[64] = "", surfaces[64] = "";
    if (args->animated) std::snprintf(motion, sizeof motion, ", animated, traffic %g", args->traffic);
    if (args->wet > 0) {
      std::snprintf(surfaces, sizeof surfaces, "%s, wet %g", args->glass ? ", glass" : "", args->wet);
    } else if (args->glass) {
      std::snprintf(surfaces, sizeof surfaces, ", glass");
    }
    std::printf("wrote %s (%s, seed %llu%s%s, %.1f MB); check it with `rigsim inspect %s`\n", out.string().c_str(),
                args->preset.c_str(), static_cast<unsigned long long>(args->seed), motion, surfaces,
                std::filesystem::file_size(out) / 1e6, out.string().c_str());
  });
}

}  // namespace rigsim::cli
