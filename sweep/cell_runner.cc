#include "sweep/cell_runner.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <mutex>
#include <stdexcept>

#include "calibrator/features.h"
#include "calibrator/semantics.h"
#include "dataset/dataset.h"
#include "evaluation/colmap_peer.h"
#include "evaluation/rig_scores.h"
#include "gltf/gltf_loader.h"
#include "pipeline/calibration_run.h"
#include "procedural/presets.h"
#include "renderer/render_dataset.h"

namespace rigsim {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

namespace {

using Clock = std::chrono::steady_clock;
double Since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

uint64_t Seed(const Json& p) { return p.at("seed").get<uint64_t>(); }

std::optional<double> OptionalNumber(const Json& p, const char* name) {
  return p.at(name).is_null() ? std::nullopt : std::optional<double>(p.at(name).get<double>());
}

bool IsPreset(const std::string& scene) {
  try {
    ScenePresetFromName(scene);
    return true;
  } catch (const std::invalid_argument&) {
    return false;
  }
}

// The scene file of a cell: a preset generated into the scene folder once (deterministic: the
// same preset, seed and animation give the same bytes), or a file named in the config.
fs::path SceneFile(const Json& p, const CellRunnerOptions& options) {
  const std::string scene = p.at("scene").get<std::string>();
  if (!IsPreset(scene)) {
    const fs::path path = fs::path(scene).is_absolute() ? fs::path(scene) : options.config_dir / scene;
    if (!fs::exists(path)) throw std::runtime_error(path.string() + ": scene file not found");
    return path;
  }
  ScenePresetOptions preset;
  preset.preset = ScenePresetFromName(scene);
  preset.seed = p.at("scene_seed").is_null() ? Seed(p) : p.at("scene_seed").get<uint64_t>();
  preset.animated = p.at("animated").get<bool>();
  preset.traffic = p.at("traffic").get<double>();
  const fs::path path = options.scene_dir / (scene + "-" + std::to_string(preset.seed) +
                                             (preset.animated ? "-animated-traffic" + FormatParamValue(p.at("traffic")) : "") + ".glb");
  if (!fs::exists(path)) {
    fs::create_directories(options.scene_dir);
    const fs::path tmp = path.string() + ".partial";
    WriteScenePreset(preset, tmp);
    fs::rename(tmp, path);
  }
  return path;
}

// The last scene loaded: a sweep's cells come in study order, so neighbours share their scene.
class SceneCache {
 public:
  const Scene& Get(const fs::path& path) {
    if (!scene_ || path != path_) {
      scene_ = std::make_unique<Scene>(LoadGltf(path));
      path_ = path;
    }
    return *scene_;
  }

 private:
  fs::path path_;
  std::unique_ptr<Scene> scene_;
};

PhotometricOptions Photometric(const Json& p) {
  const double scale = p.at("photometric").get<double>();
  PhotometricOptions o;
  if (scale <= 0) return o;
  o = PhotometricOptions::Defaults();
  o.exposure_stops_sigma *= scale;
  o.white_balance_stops_sigma *= scale;
  o.vignetting_strength = std::min(0.9, o.vignetting_strength * scale);
  o.shot_noise *= scale;
  o.read_noise_stddev *= scale;
  o.seed = Seed(p);
  return o;
}

// Mean ground-truth overlap (percent) of the camera pairs that share more than 1% of their view,
// and their count.
std::pair<std::optional<double>, int> OverlapOf(const fs::path& dataset) {
  const OverlapTable table = ReadOverlap(DatasetLayout(dataset).OverlapJson());
  double sum = 0.0;
  int n = 0;
  for (const auto& [pair, overlap] : table) {
    if (overlap <= 0.01) continue;
    sum += overlap;
    ++n;
  }
  return {n ? std::optional<double>(100.0 * sum / n) : std::nullopt, n};
}

Json OptionalJson(const std::optional<double>& v) { return v ? Json(*v) : Json(nullptr); }

// The scores every method's row has, from the estimate scored against the truth.
Json ScoreMetrics(const RigScores& s) {
  return {{"cameras", s.cameras.size()},
          {"cameras_posed", s.cameras_posed},
          {"cameras_rotation_only", s.cameras_rotation_only},
          {"success_1deg", s.success_1deg ? 1 : 0},
          {"success_2deg", s.success_2deg ? 1 : 0},
          {"confidently_wrong", s.confidently_wrong},
          {"max_rotation_error_deg", OptionalJson(s.max_rotation_error_deg)},
          {"median_rotation_error_deg", OptionalJson(s.median_rotation_error_deg)},
          {"max_translation_direction_error_deg", OptionalJson(s.max_direction_error_deg)},
          {"median_translation_direction_error_deg", OptionalJson(s.median_direction_error_deg)},
          {"max_position_error_m", OptionalJson(s.max_position_error_m)},
          {"auc_cameras_5deg", s.auc_cameras[2]},
          {"auc_pairs_1deg", s.auc_pairs[0]},
          {"auc_pairs_2deg", s.auc_pairs[1]},
          {"auc_pairs_5deg", s.auc_pairs[2]},
          {"auc_pairs_10deg", s.auc_pairs[3]}};
}

// What rigsim's calibration reported about its matches and its time.
void AddCalibrationMetrics(const RigCalibrationResult& r, Json& m) {
  int64_t matches = 0, evaluated = 0, correct = 0, cross = 0, cross_correct = 0;
  bool has_cross = false;
  for (const PairResult& pair : r.pairwise.pairs) {
    matches += pair.two_view.num_matches;
    evaluated += pair.matches_evaluated;
    correct += pair.matches_correct;
    if (pair.cross_class_matches) {
      has_cross = true;
      cross += *pair.cross_class_matches;
      cross_correct += pair.cross_class_correct;
    }
  }
  m["cross_class_matches"] = has_cross ? Json(cross) : Json(nullptr);
  m["cross_class_wrong"] = has_cross ? Json(cross - cross_correct) : Json(nullptr);
  m["cross_class_right"] = has_cross ? Json(cross_correct) : Json(nullptr);
  m["matches"] = matches;
  m["match_precision"] = evaluated > 0 ? Json(double(correct) / evaluated) : Json(nullptr);
  m["wrong_matches"] = evaluated > 0 ? Json(evaluated - correct) : Json(nullptr);
  m["time_detect_s"] = r.pairwise.detect_time_s;
  m["time_match_s"] = r.pairwise.screen_time_s + r.pairwise.match_time_s + r.pairwise.temporal_match_time_s;
}

MethodRow Failed(const std::string& method, const std::string& why) {
  MethodRow row;
  row.method = method;
  row.status = "failed";
  row.failure_reason = why;
  return row;
}

MethodRow RunRigsim(const SweepMethod& method, const Json& p, const CalibrationInputs& inputs,
                    const CellRunnerOptions& options) {
  RigCalibrationOptions o;
  o.pairwise.features.type = FeatureTypeFromName(method.features);
  o.pairwise.num_threads = options.num_threads;
  const int boundary = p.at("label_boundary").get<int>();
  const double confusion = p.at("label_confusion").get<double>();
  if (boundary > 0 || confusion > 0) {
    SegmentationNoiseOptions noise;
    noise.boundary_px = boundary;
    noise.confusion_rate = confusion;
    noise.seed = Seed(p);
    o.pairwise.labels = LabelSource::Noisy(noise);
  }
  const auto start = Clock::now();
  const CalibrationRun run = CalibrateDataset(inputs, o, {SemanticModeFromName(method.semantics)});
  MethodRow row;
  row.method = method.name;
  const RigCalibrationResult& r = run.results.at(0);
  RigEstimate estimate = RigEstimateOf(r);
  estimate.method = method.name;
  row.metrics = ScoreMetrics(ScoreRig(*inputs.truth, estimate));
  AddCalibrationMetrics(r, row.metrics);
  row.metrics["time_total_s"] = Since(start);
  return row;
}

MethodRow RunColmap(const SweepMethod& method, const CalibrationInputs& inputs, const fs::path& work,
                    const CellRunnerOptions& options) {
  ColmapPeerOptions o;
  o.num_threads = options.num_threads > 0 ? options.num_threads : 2;
  if (!ColmapAvailable(o)) return Failed(method.name, "colmap is not installed (apt-get install colmap)");
  const ColmapPeerResult peer = RunColmapPeer(inputs.dataset_dir, *inputs.truth, inputs.frames, work, o);
  if (!peer.success) return Failed(method.name, peer.failure_reason);
  MethodRow row;
  row.method = method.name;
  row.metrics = ScoreMetrics(ScoreRig(*inputs.truth, peer.estimate));
  row.metrics["time_detect_s"] = peer.extract_time_s;
  row.metrics["time_match_s"] = peer.match_time_s;
  row.metrics["time_total_s"] = peer.time_s;
  return row;
}

}  // namespace

RigSpec CellRigSpec(const Json& p) {
  RigSpec s;
  s.type = p.at("rig").get<std::string>();
  s.width = p.at("width").get<int>();
  s.height = p.at("height").get<int>();
  s.ring.num_cameras = p.at("cameras").get<int>();
  if (s.ring.distorted_camera >= s.ring.num_cameras) s.ring.distorted_camera = -1;
  s.ring.yaw_spacing_deg = p.at("spacing").get<double>();
  s.ring.radius_m = p.at("radius").get<double>();
  s.overlap_percent = OptionalNumber(p, "overlap").value_or(0.0);
  s.wide.convergence_deg = p.at("convergence").get<double>();
  s.surround.side_fov_deg = p.at("fisheye_fov").get<double>();
  s.hfov_deg = OptionalNumber(p, "hfov");
  s.baseline_m = OptionalNumber(p, "baseline");
  const std::string lens = p.at("lens").get<std::string>();
  if (lens != "preset") {
    LensOptions l;
    l.kind = LensKindFromName(lens);
    l.k1 = p.at("distortion").get<double>();
    l.fisheye_fov_deg = p.at("fisheye_fov").get<double>();
    s.lens = l;
  }
  s.trajectory.kind = p.at("trajectory").get<std::string>() == "circle" ? TrajectoryKind::kCircle : TrajectoryKind::kStraight;
  s.trajectory.num_frames = p.at("frames").get<int>();
  s.trajectory.step_m = p.at("step").get<double>();
  s.trajectory.circle_radius_m = p.at("circle_radius").get<double>();
  s.placement.seed = Seed(p);
  return s;
}

CellRunner MakeCellRunner(const SweepConfig& config, const CellRunnerOptions& options) {
  auto cache = std::make_shared<SceneCache>();
  return [config, options, cache](const SweepCell& cell, const fs::path& work,
                                  const std::function<void(const std::string&)>& status) {
    const Json& p = cell.params;
    CellRecord record;
    const auto fail_all = [&](const std::string& why) {
      for (const SweepMethod& m : config.methods) record.rows.push_back(Failed(m.name, why));
      return record;
    };
    const fs::path dataset = work / "dataset";
    {
      status("scene");
      const fs::path scene_file = SceneFile(p, options);
      const Scene& scene = cache->Get(scene_file);
      status("placing the rig");
      const RigSpec spec = CellRigSpec(p);
      std::optional<PlacedRig> placed = MakePlacedRig(spec, &scene);
      if (!placed) return fail_all("no place in the scene where the rig stands on the ground with every camera clear");
      const double offset_s = p.at("time_offset_ms").get<double>() / 1000.0;
      for (size_t c = 0; c < placed->rig.cameras.size(); ++c) placed->rig.cameras[c].time_offset_s = c * offset_s;
      RenderJob job;
      job.scene = &scene;
      job.scene_name = scene_file.filename().string();
      job.rig = placed->rig;
      job.frames = placed->frames;
      job.options.samples_per_pixel = p.at("spp").get<int>();
      job.options.seed = Seed(p);
      job.options.num_threads = options.num_threads;
      job.photometric = Photometric(p);
      status("rendering");
      const auto start = Clock::now();
      RenderDataset(job, dataset, false, [&](int, int) { status("rendering"); });
      record.cell_metrics["render_time_s"] = Since(start);
    }
    const auto [overlap, overlapping] = OverlapOf(dataset);
    record.cell_metrics["overlap_pct"] = OptionalJson(overlap);
    record.cell_metrics["overlapping_pairs"] = overlapping;
    const CalibrationInputs inputs = ReadCalibrationInputs(dataset);
    for (const SweepMethod& method : config.methods) {
      status(method.name);
      try {
        record.rows.push_back(method.tool == "colmap" ? RunColmap(method, inputs, work / "colmap", options)
                                                      : RunRigsim(method, p, inputs, options));
      } catch (const std::exception& e) {
        // A method that cannot run on this cell (its input refused) is a result of the cell.
        record.rows.push_back(Failed(method.name, e.what()));
      }
    }
    return record;
  };
}

}  // namespace rigsim
