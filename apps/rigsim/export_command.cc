// rigsim export DATASET --format kalibr|opencv|colmap|nerfstudio|all --out DIR [--rig RIG.json]
//
// An estimate's rig.json (estimate_gauge.h) is exported with its own rig trajectory, the
// frames.json beside it: its cam_from_rig are in its gauge and scale, the dataset's frames.json in
// the truth's, and the two together would place every image wrongly.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "apps/rigsim/calibrate_support.h"
#include "apps/rigsim/commands.h"
#include "apps/rigsim/render_support.h"
#include "common/format.h"
#include "dataset/dataset.h"
#include "dataset/output_folder.h"
#include "exports/colmap.h"
#include "exports/kalibr.h"
#include "exports/nerfstudio.h"
#include "exports/opencv_yaml.h"
#include "geometry/estimate_gauge.h"
#include "geometry/json_io.h"
#include "geometry/rig.h"
#include "pipeline/calibration_run.h"

namespace rigsim::cli {
namespace {

// An estimate's frames with a rig pose; the others (no temporal match chained them to the first
// frame) are left out with a warning, as cameras without a pose are.
FramesFile FramesWithPose(const FramesFile& frames, const std::filesystem::path& frames_json) {
  FramesFile posed = frames;
  posed.frames.clear();
  std::string left_out;
  for (const Frame& f : frames.frames) {
    if (f.rig_from_world) {
      posed.frames.push_back(f);
    } else {
      left_out += (left_out.empty() ? "" : ", ") + f.name;
    }
  }
  if (posed.frames.empty()) throw std::runtime_error(frames_json.string() + ": no frame has an estimated rig pose");
  if (!left_out.empty()) {
    std::fprintf(stderr, "warning: %s: leaving out the frames without an estimated rig pose: %s\n",
                 frames_json.string().c_str(), left_out.c_str());
  }
  return posed;
}

// The colmap and nerfstudio exports name every camera's photo of every frame: a photo that is not
// there would be a reference to nothing, found only when another tool reads the export.
// `which` says which exports name them: "the colmap export names".
void RequirePhotos(const DatasetLayout& layout, const Rig& rig, const FramesFile& frames, const std::string& which) {
  std::vector<std::string> missing;
  for (const Frame& f : frames.frames) {
    for (const RigCamera& c : rig.cameras) {
      if (!layout.FindImage(c.name, f.name)) missing.push_back(c.name + "/" + f.name + ".*");
    }
  }
  if (missing.empty()) return;
  std::string list;
  const size_t shown = std::min<size_t>(missing.size(), 3);
  for (size_t i = 0; i < shown; ++i) list += (i > 0 ? ", " : "") + missing[i];
  if (missing.size() > shown) list += " and " + std::to_string(missing.size() - shown) + " more";
  throw std::runtime_error((layout.root() / "images").string() + ": " + std::to_string(missing.size()) + " of the " +
                           std::to_string(rig.cameras.size() * frames.frames.size()) + " photos " + which +
                           " are missing (" + list + "); render or copy them there, or export only " +
                           "--format kalibr,opencv, which name no photo");
}

}  // namespace

void AddExportCommand(CLI::App& app) {
  struct Args {
    std::string dataset, out, rig;
    std::vector<std::string> formats = {"all"};
    bool force = false;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "export",
      "Export a dataset's rig (ground truth, or an estimate with --rig) for other tools:\n"
      "  kalibr      OUT/camchain.yaml (T_cn_cnm1 chain, pinhole + radtan/equidistant)\n"
      "  opencv      OUT/opencv.yaml (cv::FileStorage: camera_matrix, distortion_coefficients, R, T)\n"
      "  colmap      OUT/colmap/{cameras,images,points3D}.txt (images named <cam>/<frame> under DATASET/images;\n"
      "              cx, cy + 0.5 for COLMAP's pixel convention)\n"
      "  nerfstudio  OUT/transforms.json (per image: world_from_cam in OpenGL axes and intrinsics)\n"
      "An estimate (a rig.json written by calibrate) is exported with its own rig poses, the frames.json beside\n"
      "it, in its own frame and unit of length, which every file states; the truth with the dataset's.\n"
      "The output folder appears only when complete.");
  cmd->add_option("dataset", args->dataset, "dataset folder (rig.json, frames.json, images/)")
      ->required()
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--format", args->formats, "kalibr, opencv, colmap, nerfstudio or all (comma-separated)")
      ->delimiter(',')
      ->capture_default_str()
      ->check(CLI::IsMember({"kalibr", "opencv", "colmap", "nerfstudio", "all"}));
  cmd->add_option("--out", args->out, "output folder (created; see --force)")->required();
  cmd->add_option("--rig", args->rig, "export this rig.json (e.g. a calibration estimate) instead of DATASET/rig.json")
      ->check(CLI::ExistingFile);
  cmd->add_flag("--force", args->force, "replace an existing output folder");
  cmd->callback([args] {
    std::set<std::string> formats(args->formats.begin(), args->formats.end());
    if (formats.count("all")) formats = {"kalibr", "opencv", "colmap", "nerfstudio"};
    const DatasetLayout layout(args->dataset);
    const std::filesystem::path rig_json = args->rig.empty() ? layout.RigJson() : std::filesystem::path(args->rig);
    const std::string rig_text = json_io::ReadText(rig_json);
    const std::optional<EstimateGauge> gauge = EstimateGaugeFromJsonText(rig_text, rig_json.string());
    const bool needs_frames = formats.count("colmap") || formats.count("nerfstudio");
    const std::filesystem::path frames_json = gauge ? rig_json.parent_path() / gauge->frames : layout.FramesJson();
    if (gauge && needs_frames && (gauge->frames.empty() || !std::filesystem::is_regular_file(frames_json))) {
      throw std::runtime_error(
          rig_json.string() + ": a calibration estimate (" + gauge->LengthUnit() + ") whose rig poses " +
          (gauge->frames.empty() ? std::string("are not given") : "(" + frames_json.string() + ") are missing") +
          ": the colmap and nerfstudio exports need the rig's pose at every frame in the estimate's own frame and "
          "scale, not the dataset's; calibrate the dataset again (it writes frames.json beside rig.json), or export "
          "--format kalibr,opencv");
    }
    OutputFolderRequest out{args->out, "--out", "rigsim export", {}, args->force};
    out.inputs = {{rig_json, args->rig.empty() ? "the dataset's rig.json" : "--rig"},
                  {frames_json, gauge ? "the estimate's frames.json" : "the dataset's frames.json"},
                  {layout.root() / "images", "the dataset's images/"}};
    CheckReplaceableOutput(out);
    Rig rig = RigFromJsonText(rig_text, rig_json.string());
    // A calibration estimate may leave cameras without a pose: they are left out of every format,
    // as calibrate's own exports do. A rig with no pose at all exports its intrinsics (opencv).
    if (const Rig posed = rig.PosedCameras(); !posed.cameras.empty() && posed.cameras.size() < rig.cameras.size()) {
      std::fprintf(stderr, "warning: %s: leaving out the cameras without cam_from_rig (not calibrated): %s\n",
                   rig_json.string().c_str(), CamerasWithoutPose(rig).c_str());
      rig = posed;
    }
    FramesFile frames;
    if (needs_frames) {
      if (!std::filesystem::exists(frames_json)) {
        throw std::runtime_error(frames_json.string() + ": missing; colmap and nerfstudio exports need the frame poses");
      }
      frames = ReadFrames(frames_json);
      if (gauge) frames = FramesWithPose(frames, frames_json);
      RequirePoses(rig, rig_json, frames, frames_json, "the colmap and nerfstudio exports");
      const bool both = formats.count("colmap") && formats.count("nerfstudio");
      RequirePhotos(layout, rig, frames,
                    both ? "the colmap and nerfstudio exports name" : formats.count("colmap") ? "the colmap export names" : "the nerfstudio export names");
    }
    // Images are named as the dataset has them, whatever their extension.
    const ImageNameFn image_name = [&layout](const std::string& cam, const std::string& frame) {
      return layout.ImageName(cam, frame);
    };
    StagedOutput staged(out);
    const std::filesystem::path& dir = staged.staging_dir();
    std::vector<std::string> written;
    if (formats.count("kalibr")) {
      WriteKalibrCamchain(rig, dir / "camchain.yaml", gauge);
      written.push_back("camchain.yaml");
    }
    if (formats.count("opencv")) {
      WriteOpenCvRigYaml(rig, dir / "opencv.yaml", gauge);
      written.push_back("opencv.yaml");
    }
    if (formats.count("colmap")) {
      ColmapExportOptions o;
      o.image_name = image_name;
      o.gauge = gauge;
      WriteColmapModel(rig, frames, dir / "colmap", o);
      written.push_back("colmap/");
    }
    if (formats.count("nerfstudio")) {
      NerfstudioExportOptions o;
      o.image_name = image_name;
      o.gauge = gauge;
      const auto out_abs = std::filesystem::absolute(args->out).lexically_normal();
      const auto images_abs = std::filesystem::absolute(layout.root() / "images").lexically_normal();
      o.image_prefix = images_abs.lexically_relative(out_abs).generic_string();
      WriteNerfstudioTransforms(rig, frames, dir, o);
      for (const NerfstudioFile& f : NerfstudioTransforms(rig, frames, o)) written.push_back(f.filename);
    }
    staged.Commit();
    std::string list;
    for (const std::string& w : written) list += " " + w;
    std::printf("exported %s%s to %s:%s\n", Count(rig.cameras.size(), "camera").c_str(),
                frames.frames.empty() ? "" : (" x " + Count(frames.frames.size(), "frame")).c_str(), args->out.c_str(),
                list.c_str());
    if (gauge) {
      std::printf("%s%s\n", gauge->Describe().c_str(),
                  needs_frames ? ("; rig poses from " + frames_json.string()).c_str() : "");
    }
    if (formats.count("colmap")) {
      const std::filesystem::path model = std::filesystem::path(args->out) / "colmap";
      std::printf("COLMAP: --image_path %s --input_path %s; its points at these poses: bash %s %s OUT_DIR\n",
                  (layout.root() / "images").string().c_str(), model.string().c_str(), (model / "triangulate.sh").string().c_str(),
                  (layout.root() / "images").string().c_str());
    }
  });
}

}  // namespace rigsim::cli
