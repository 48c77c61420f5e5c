#include "apps/rigsim/calibrate_support.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <optional>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "apps/rigsim/commands.h"
#include "apps/rigsim/report_table.h"
#include "calibrator/match_image.h"
#include "dataset/dataset.h"
#include "dataset/image_io.h"
#include "exports/colmap.h"
#include "exports/kalibr.h"
#include "exports/opencv_yaml.h"
#include "exports/rig_plot.h"
#include "geometry/camera_validation.h"
#include "geometry/json_io.h"

namespace rigsim::cli {

LabelSource LabelSettings::ToSource() const {
  if (labels != "noisy") {
    for (const CLI::Option* opt : noise_options) {
      if (opt->count() > 0) throw std::invalid_argument(opt->get_name() + " needs --labels noisy (got --labels " + labels + ")");
    }
  }
  LabelSource source;
  if (labels == "truth") {
    source = LabelSource::Truth();
  } else if (labels == "noisy") {
    source = LabelSource::Noisy(noise);
  } else if (labels.empty()) {
    throw std::invalid_argument("--labels: give truth, noisy or a folder");
  } else {
    source = LabelSource::Folder(labels);
  }
  source.Check();
  return source;
}

void AddLabelSourceOptions(CLI::App& cmd, LabelSettings& s) {
  const SegmentationNoiseOptions d = LabelSettings::DefaultNoise();
  cmd.add_option("--labels", s.labels,
                 "labels for the semantic modes: truth (DATASET/labels, as rendered), noisy (the truth through\n"
                 "a seeded model of a segmentation network's errors, see --label-noise-*), or a folder DIR\n"
                 "holding DIR/<cam>/<frame>.png as Cityscapes label ids (1 channel) or Cityscapes colours\n"
                 "(RGB), told apart per file (DATASET/labels_color works). A folder named truth or noisy: ./truth")
      ->capture_default_str();
  s.noise_options.push_back(
      cmd.add_option("--label-noise-boundary", s.noise.boundary_px,
                     "noisy: class boundaries move by up to PX pixels (each class grows or shrinks, varying\n"
                     "along the boundary)")
          ->default_str(std::to_string(d.boundary_px))
          ->check(CLI::Range(0, 64)));
  s.noise_options.push_back(
      cmd.add_option("--label-noise-confusion", s.noise.confusion_rate,
                     "noisy: probability that a blob (a class's region within a superpixel) is relabelled\n"
                     "to a class networks confuse it with (road/sidewalk, building/wall, car/truck, ...)")
          ->default_str("0.1")
          ->check(CLI::Range(0.0, 1.0)));
  s.noise_options.push_back(cmd.add_option("--label-noise-blob", s.noise.blob_size_px,
                                           "noisy: superpixel size of the confused blobs (px)")
                                ->default_str(std::to_string(d.blob_size_px))
                                ->check(CLI::Range(4, 4096)));
  s.noise_options.push_back(
      cmd.add_option("--label-noise-seed", s.noise.seed,
                     "noisy: seed; every image's errors depend only on (seed, camera, frame)")
          ->default_str(std::to_string(d.seed)));
}

RigCalibrationOptions CalibrateSettings::ToOptions() const {
  RigCalibrationOptions o = options;
  o.pairwise.labels = labels.ToSource();
  if (!reliable.empty()) o.pairwise.reliable = ReliableClasses::FromNames(reliable);
  if (!known_distance.empty()) {
    if (known_distance.size() != 3) throw std::invalid_argument("--known-distance takes CAM_A CAM_B METRES");
    double metres = 0.0;
    try {
      metres = std::stod(known_distance[2]);
    } catch (const std::exception&) {
      throw std::invalid_argument("--known-distance: '" + known_distance[2] + "' is not a number of metres");
    }
    if (known_distance[0] == known_distance[1]) {
      throw std::invalid_argument("--known-distance: give two different cameras (got '" + known_distance[0] + "' twice)");
    }
    o.known_distance = KnownDistance{known_distance[0], known_distance[1], metres};
  }
  o.Check();
  return o;
}

std::vector<SemanticMode> CalibrateSettings::Modes() const {
  std::vector<SemanticMode> modes;
  for (const std::string& s : semantics) modes.push_back(SemanticModeFromName(s));
  if (modes.empty()) throw std::invalid_argument("--semantics: give at least one mode");
  return modes;
}

void AddCalibrateSettingsOptions(CLI::App& cmd, CalibrateSettings& s) {
  cmd.add_option("--semantics", s.semantics,
                 "semantic modes to compare on the same images: none (baseline), mask (features only on\n"
                 "reliable classes), gated (match only within a class), mask+gated")
      ->delimiter(',')
      ->capture_default_str();
  cmd.add_option("--reliable", s.reliable,
                 "Cityscapes class names to treat as reliable, comma-separated (default: static structure:\n"
                 "ground, road, sidewalk, parking, rail track, building, wall, fence, guard rail, bridge,\n"
                 "tunnel, pole, polegroup, traffic light, traffic sign)")
      ->delimiter(',');
  cmd.add_option("--known-distance", s.known_distance,
                 "CAM_A CAM_B METRES: distance between two camera centres, the only source of metric\n"
                 "scale; without it the result has unit scale")
      ->expected(3);
  FeatureOptions& features = s.options.pairwise.features;
  cmd.add_option("--max-features", features.max_features, "strongest keypoints kept per image (every --features type)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd.add_option("--sift-contrast", features.contrast_threshold,
                 "SIFT contrast threshold; lower finds more, weaker keypoints")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd.add_option("--screen-features", s.options.pairwise.screen_features,
                 "pair screening: match only this many strongest keypoints of two frames first and\n"
                 "skip the full matching of pairs that show no shared view; 0 matches every pair in full")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd.add_option("--ratio", s.options.pairwise.matching.ratio,
                 "Lowe's ratio test: keep a match when best < ratio x second best")
      ->capture_default_str()
      ->check(CLI::Range(0.1, 1.0));
  cmd.add_option("--max-error-px", s.options.pairwise.two_view.max_error_px,
                 "inlier threshold of the robust relative-pose fit (px)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  if (cmd.get_option_no_throw("--threads") == nullptr) {
    cmd.add_option("--threads", s.options.pairwise.num_threads, "worker threads, 0 = all cores")
        ->capture_default_str()
        ->check(CLI::NonNegativeNumber);
  }
}

void CheckCalibrationInputs(const std::filesystem::path& dataset) {
  const DatasetLayout layout(dataset);
  const Rig rig = ReadRig(layout.RigJson());
  for (const std::string& w : CheckRigCoversImages(rig, layout.RigJson().string())) {
    std::fprintf(stderr, "warning: %s\n", w.c_str());
  }
  const size_t posed = rig.PosedCameras().cameras.size();
  if (posed > 0 && posed < rig.cameras.size()) {
    std::fprintf(stderr,
                 "warning: %s: cam_from_rig given for %zu of %zu cameras (not for %s): the estimate is not compared "
                 "with the truth, which needs every camera's\n",
                 layout.RigJson().string().c_str(), posed, rig.cameras.size(), CamerasWithoutPose(rig).c_str());
  }
}

std::string CamerasWithoutPose(const Rig& rig) {
  std::string names;
  for (const RigCamera& rc : rig.cameras) {
    if (!rc.cam_from_rig) names += (names.empty() ? "" : ", ") + rc.name;
  }
  return names;
}

namespace {

namespace fs = std::filesystem;

// evaluation.json: the pairwise report of each method (ReportToJson) with the rig result of the
// same method under "rig".
json_io::Json EvaluationJson(const std::vector<RigCalibrationResult>& results) {
  std::vector<CalibrationReport> pairwise;
  for (const RigCalibrationResult& r : results) pairwise.push_back(r.pairwise);
  json_io::Json evaluation = ReportToJson(pairwise);
  const json_io::Json rig = RigCalibrationToJson(results);
  for (const RigCalibrationResult& r : results) {
    json_io::Json entry = rig["methods"][r.semantic_mode];
    entry.erase("pairwise");  // already the method's own entry
    evaluation["methods"][r.semantic_mode]["rig"] = entry;
  }
  return evaluation;
}

json_io::Json LabelSourceJson(const LabelSource& source, bool used) {
  json_io::Json j = {{"kind", source.KindName()}, {"description", source.Describe()}, {"used", used}};
  if (source.kind == LabelSource::Kind::kFolder) j["folder"] = fs::absolute(source.folder).lexically_normal().string();
  if (source.kind == LabelSource::Kind::kNoisy) {
    j["noise"] = {{"boundary_px", source.noise.boundary_px},
                  {"confusion_rate", source.noise.confusion_rate},
                  {"blob_size_px", source.noise.blob_size_px},
                  {"seed", source.noise.seed}};
  }
  return j;
}

// The pair's type: two_view.h's ("general", "planar", "rotation-only") when the pair JSON has it,
// "general" or "rotation-only" from the flags otherwise, and "failed" when there is no estimate.
std::string PairTypeOf(const json_io::Json& pair) {
  if (!pair.value("success", false)) return "failed";
  if (pair.contains("pair_type") && pair["pair_type"].is_string()) return pair["pair_type"].get<std::string>();
  return pair.value("rotation_only", false) ? "rotation-only" : "general";
}

// pairs.json of one mode: every camera pair's pairwise statistics (ReportToJson's entries) with
// its type, the ground-truth overlap when overlap.json has it, and what the rig stage made of it.
json_io::Json PairsJson(const json_io::Json& method, const std::string& mode, const json_io::Json& label_source,
                        const OverlapTable& overlap) {
  json_io::Json pairs = json_io::Json::array();
  for (json_io::Json pair : method["pairs"]) {
    const std::string a = pair["cam_a"], b = pair["cam_b"];
    pair["pair_type"] = PairTypeOf(pair);
    const auto ov = overlap.find({a, b});
    pair["overlap"] = ov != overlap.end() ? json_io::Json(ov->second) : json_io::Json(nullptr);
    pair["rig_edge"] = nullptr;
    for (const json_io::Json& e : method["rig"]["edges"]) {
      if (e["cam_a"] == a && e["cam_b"] == b) {
        pair["rig_edge"] = {{"used", e["used"]},
                            {"status", e["status"]},
                            {"rotation_outlier", e["rotation_outlier"]},
                            {"rotation_residual_deg", e["rotation_residual_deg"]}};
      }
    }
    pairs.push_back(std::move(pair));
  }
  return {{"semantic_mode", mode},
          {"label_source", label_source},
          {"num_frames", method["num_frames"]},
          {"units",
           {{"median_residual_deg", "median angular epipolar residual of the pair's two-view inliers (deg)"},
            {"rotation_error_deg", "angle of R_est R_true^T (deg), when rig.json has the truth"},
            {"translation_direction_error_deg", "angle between estimated and true baseline directions (deg)"},
            {"rig_edge.rotation_residual_deg", "the final rig's relative rotation vs this pair's (deg)"}}},
          {"pairs", pairs}};
}

// The exports of one mode's estimate (the writers of `rigsim export`): camchain.yaml, opencv.yaml
// and colmap/, of the cameras with a full pose only. COLMAP gets the images of every frame with a
// rig pose, cam_from_world = cam_from_rig * rig_from_world, in the calibration's world (the rig
// frame at frame 0). And rig_topdown.svg, the estimate against `truth` (when known) seen from
// above. Returns the "outputs" record.
json_io::Json WriteExports(const RigCalibrationResult& r, const std::optional<Rig>& truth, const DatasetLayout& layout,
                           const FramesFile& frames, const fs::path& dir) {
  const Rig calibrated = r.rig.PosedCameras();
  json_io::Json exported = json_io::Json::array(), omitted = json_io::Json::array(), notes = json_io::Json::array();
  json_io::Json colmap_frames = json_io::Json::array(), colmap_frames_omitted = json_io::Json::array();
  for (size_t c = 0; c < r.rig.cameras.size(); ++c) {
    const RigCamera& rc = r.rig.cameras[c];
    if (rc.cam_from_rig) {
      exported.push_back(rc.name);
    } else {
      omitted.push_back({{"name", rc.name}, {"status", c < r.camera_status.size() ? r.camera_status[c] : ""}});
    }
  }
  json_io::Json files = {"rig.json", "pairs.json"};
  auto note = [&](const std::string& text) {
    std::fprintf(stderr, "warning: %s: %s\n", r.semantic_mode.c_str(), text.c_str());
    notes.push_back(text);
  };
  if (!omitted.empty()) {
    std::string names;
    for (const auto& o : omitted) names += (names.empty() ? "" : ", ") + o["name"].get<std::string>();
    note("camchain.yaml, opencv.yaml and colmap/ leave out the cameras without a full pose: " + names +
         " (see rig.json and evaluation.json for why)");
  }
  RigPlotInput plot;
  plot.estimate = r.rig;
  plot.truth = truth;
  plot.metric = r.metric_scale;
  for (size_t c = 0; c < r.rig.cameras.size(); ++c) {
    const bool rotation_only = !r.rig.cameras[c].cam_from_rig && c < r.cam_from_rig_rotation.size();
    plot.rotation_only.push_back(rotation_only ? r.cam_from_rig_rotation[c] : std::nullopt);
  }
  plot.title = "rigsim calibrate, " + r.semantic_mode + ": " + std::to_string(exported.size()) + " of " +
               std::to_string(r.rig.cameras.size()) + " cameras with a full pose";
  try {
    json_io::WriteTextAtomic(dir / "rig_topdown.svg", RigTopDownSvg(plot));
    files.push_back("rig_topdown.svg");
  } catch (const std::invalid_argument& e) {
    note(std::string("rig_topdown.svg not written: ") + e.what());
  }
  if (calibrated.cameras.empty()) {
    note("no camera has a pose: no camchain.yaml, opencv.yaml or colmap/");
  } else {
    try {
      WriteKalibrCamchain(calibrated, dir / "camchain.yaml");
      files.push_back("camchain.yaml");
    } catch (const std::invalid_argument& e) {  // a model Kalibr cannot express
      note(std::string("camchain.yaml not written: ") + e.what());
    }
    WriteOpenCvRigYaml(calibrated, dir / "opencv.yaml");
    files.push_back("opencv.yaml");
    FramesFile posed;
    for (size_t k = 0; k < frames.frames.size(); ++k) {
      const Frame& f = frames.frames[k];
      std::optional<Rigid3d> rig_from_world;
      if (k < r.rig_from_world.size()) {
        rig_from_world = r.rig_from_world[k];
      } else if (k == 0) {
        rig_from_world = Rigid3d();  // without positions only frame 0 has a pose: its rig frame is the world
      }
      if (rig_from_world) {
        posed.frames.push_back(Frame{f.name, rig_from_world, f.timestamp_s});
      } else {
        colmap_frames_omitted.push_back(f.name);
      }
    }
    ColmapExportOptions colmap;
    colmap.image_name = [&layout](const std::string& cam, const std::string& frame) { return layout.ImageName(cam, frame); };
    WriteColmapModel(calibrated, posed, dir / "colmap", colmap);
    for (const Frame& f : posed.frames) colmap_frames.push_back(f.name);
    files.push_back("colmap/cameras.txt");
    files.push_back("colmap/images.txt");
    files.push_back("colmap/points3D.txt");
  }
  return {{"dir", r.semantic_mode},
          {"files", files},
          {"cameras_exported", exported},
          {"cameras_omitted", omitted},
          {"colmap_frames", colmap_frames},
          {"colmap_frames_omitted", colmap_frames_omitted},
          {"notes", notes}};
}

// <mode>/matches/<cam_a>-<cam_b>.jpg: each pair's two-view inliers in its best frame, drawn over
// the two photos, pairs in parallel (decoding two 6-megapixel JPEGs per pair is most of the work).
// Returns the files written (relative to `dir`), in the pairs' order.
std::vector<std::string> WriteMatchImages(const RigCalibrationResult& r, const DatasetLayout& layout,
                                          const FramesFile& frames, const fs::path& dir, int num_threads) {
  std::vector<std::string> written(r.inlier_samples.size());
  fs::create_directories(dir / "matches");
  tbb::task_arena arena(num_threads > 0 ? num_threads : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(size_t(0), r.inlier_samples.size(), [&](size_t i) {
      const PairInlierSample& s = r.inlier_samples[i];
      if (s.frame < 0 || size_t(s.frame) >= frames.frames.size()) return;
      const std::string& frame = frames.frames[s.frame].name;
      const auto path_a = layout.FindImage(s.cam_a, frame), path_b = layout.FindImage(s.cam_b, frame);
      if (!path_a || !path_b) return;
      const std::string name = "matches/" + s.cam_a + "-" + s.cam_b + ".jpg";
      WriteImage(dir / name, DrawMatches(ReadImageU8(*path_a, 3), ReadImageU8(*path_b, 3), s.points));
      written[i] = name;
    });
  });
  std::vector<std::string> files;
  for (std::string& name : written) {
    if (!name.empty()) files.push_back(std::move(name));
  }
  if (files.empty()) fs::remove(dir / "matches");
  return files;
}

}  // namespace

std::vector<RigCalibrationResult> CalibrateAndReport(const std::filesystem::path& dataset, const CalibrateSettings& settings,
                                                     const std::filesystem::path& out_dir, bool force) {
  const RigCalibrationOptions options = settings.ToOptions();
  const std::vector<SemanticMode> modes = settings.Modes();
  const bool labels_used = std::any_of(modes.begin(), modes.end(), NeedsLabels);
  const LabelSource& labels = options.pairwise.labels;
  if (!labels_used && labels.kind != LabelSource::Kind::kTruth) {
    std::fprintf(stderr, "warning: --labels %s is not used: no semantic mode given needs labels\n",
                 settings.labels.labels.c_str());
  }
  // Everything that can be checked cheaply is checked before the long run, so that bad input
  // fails fast and leaves nothing behind.
  const DatasetLayout layout(dataset);
  const OverlapTable overlap = ReadOverlap(layout.OverlapJson());
  CheckCalibrationInputs(dataset);
  StagedOutput staged(out_dir, force);

  const auto start = std::chrono::steady_clock::now();
  std::fprintf(stderr, "calibrating %s (%zu semantic modes%s)...\n", dataset.string().c_str(), modes.size(),
               labels_used ? (", labels: " + labels.Describe()).c_str() : "");
  const std::vector<RigCalibrationResult> results = CalibrateRig(dataset, options, modes);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  const Rig dataset_rig = ReadRig(layout.RigJson());
  const FramesFile frames = layout.ReadFramesOrScan(dataset_rig.cameras.at(0).name);
  const std::optional<Rig> truth = dataset_rig.HasAllPoses() ? std::optional<Rig>(dataset_rig) : std::nullopt;
  json_io::Json evaluation = EvaluationJson(results);
  evaluation["label_source"] = LabelSourceJson(labels, labels_used);
  for (const RigCalibrationResult& r : results) {
    const fs::path dir = staged.staging_dir() / r.semantic_mode;
    fs::create_directories(dir);
    WriteRig(r.rig, dir / "rig.json");
    json_io::Json& method = evaluation["methods"][r.semantic_mode];
    json_io::WriteTextAtomic(dir / "pairs.json",
                             PairsJson(method, r.semantic_mode, evaluation["label_source"], overlap).dump(2) + "\n");
    method["outputs"] = WriteExports(r, truth, layout, frames, dir);
    for (const std::string& file : WriteMatchImages(r, layout, frames, dir, options.pairwise.num_threads)) {
      method["outputs"]["files"].push_back(file);
    }
  }
  json_io::WriteTextAtomic(staged.staging_dir() / "evaluation.json", evaluation.dump(2) + "\n");
  staged.Commit();

  std::vector<CalibrationReport> pairwise;
  for (const RigCalibrationResult& r : results) pairwise.push_back(r.pairwise);
  std::printf("\nRelative pose of every camera pair (matches of %d frame(s) pooled):\n\n",
              pairwise.empty() ? 0 : pairwise[0].num_frames);
  std::printf("%s\n", FormatPairTable(pairwise, overlap).c_str());
  std::printf("%s\n", FormatSummary(pairwise, overlap).c_str());
  std::printf("Rig: every camera's pose (gauge: %s is the rig frame; errors after aligning it):\n\n",
              results.empty() || results[0].rig.cameras.empty() ? "camera 0" : results[0].rig.cameras[0].name.c_str());
  std::printf("%s\n", FormatRigTable(results).c_str());
  std::printf("%s", FormatRigSummary(results).c_str());
  std::printf("calibration took %.1f s; labels: %s; results in %s:\n", seconds,
              labels_used ? labels.Describe().c_str() : "not used", out_dir.string().c_str());
  std::printf("  evaluation.json; per mode <mode>/: rig.json, camchain.yaml (Kalibr), opencv.yaml, colmap/, pairs.json,\n"
              "  rig_topdown.svg (the rig seen from above%s), matches/ (each solved pair's inliers)\n",
              results.empty() || !truth ? "" : ", against the truth");
  return results;
}

void ThrowUnlessEveryCameraCalibrated(const std::vector<RigCalibrationResult>& results) {
  std::string missing;
  for (const RigCalibrationResult& r : results) {
    if (const std::string names = CamerasWithoutPose(r.rig); !names.empty()) {
      missing += (missing.empty() ? "" : "; ") + r.semantic_mode + ": " + names;
    }
  }
  if (!missing.empty()) {
    throw Unfinished(3, "not every camera was calibrated (" + missing +
                            "); the results are written, the camera table above says why");
  }
}

}  // namespace rigsim::cli
