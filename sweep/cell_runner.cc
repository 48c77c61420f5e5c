#include "sweep/cell_runner.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <memory>
#include <mutex>
#include <set>
#include <stdexcept>

#include "calibrator/features/features.h"
#include "calibrator/features/semantics.h"
#include "dataset/dataset.h"
#include "evaluation/colmap_peer.h"
#include "evaluation/rig_scores.h"
#include "gltf/gltf_loader.h"
#include "pipeline/calibration_run.h"
#include "procedural/ego_vehicle.h"
#include "procedural/presets.h"
#include "renderer/render_dataset.h"
#include "rigs/rig_params.h"
#include "sweep/sweep_metrics.h"

namespace rigsim {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

namespace {

using Clock = std::chrono::steady_clock;
double Since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

uint64_t Seed(const Json& p) { return p.at("seed").get<uint64_t>(); }

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
fs::path SceneFile(const Json& p, const CellRunnerOptions& options,
                   const std::function<void(const std::string&)>& status) {
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
    status(kOneOffStage);
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

MethodRow Failed(const std::string& method, const std::string& why) {
  MethodRow row;
  row.method = method;
  row.status = "failed";
  row.failure_reason = why;
  return row;
}

MethodRow RunRigsim(const SweepMethod& method, const Json& p, const CalibrationInputs& inputs,
                    const CellRunnerOptions& options) {
  const CalibrationRunOptions o = CellCalibrationOptions(method, p, options.num_threads);
  const auto start = Clock::now();
  const CalibrationRun run = CalibrateDataset(inputs, o, {SemanticModeFromName(method.semantics)});
  const RigCalibrationResult& r = run.results.at(0);
  RigEstimate estimate = RigEstimateOf(r);
  estimate.method = method.name;
  const RigScores scores = ScoreRig(*inputs.truth, estimate);
  MethodRow row;
  row.method = method.name;
  row.metrics = MethodMetrics({&scores, &r, nullptr, Since(start), &run.records.at(0)});
  return row;
}

MethodRow RunColmap(const SweepMethod& method, const CalibrationInputs& inputs, const fs::path& work,
                    const CellRunnerOptions& options) {
  ColmapPeerOptions o;
  o.num_threads = options.num_threads > 0 ? options.num_threads : 2;
  if (!ColmapAvailable(o)) return Failed(method.name, "colmap is not installed (apt-get install colmap)");
  const ColmapPeerResult peer = RunColmapPeer(inputs.dataset_dir, *inputs.truth, inputs.frames, work, o);
  if (!peer.success) return Failed(method.name, peer.failure_reason);
  const RigScores scores = ScoreRig(*inputs.truth, peer.estimate);
  MethodRow row;
  row.method = method.name;
  row.metrics = MethodMetrics({&scores, nullptr, &peer, peer.time_s});
  return row;
}

}  // namespace

CalibrationRunOptions CellCalibrationOptions(const SweepMethod& method, const Json& p, int num_threads) {
  CalibrationRunOptions o;
  o.features.type = FeatureTypeFromName(method.features);
  o.rig.pairwise.num_threads = num_threads;
  o.rig.capture_time.estimate_offsets = method.time != "synchronised";
  o.rig.capture_time.estimate_readout = method.time == "estimated+rolling-shutter";
  const int boundary = p.at("label_boundary").get<int>();
  const double confusion = p.at("label_confusion").get<double>();
  if (boundary > 0 || confusion > 0) {
    SegmentationNoiseOptions noise;
    noise.boundary_px = boundary;
    noise.confusion_rate = confusion;
    noise.seed = Seed(p);
    o.labels = LabelSource::Noisy(noise);
  }
  o.intrinsics_error = {p.at("intrinsics_error").get<double>(), Seed(p)};
  return o;
}

RigSpec CellRigSpec(const Json& p, const fs::path& config_dir) {
  Json values = Json::object();
  for (const RigParam& r : RigParams()) {
    if (r.in_sweep) values[r.spec.name] = CellParam(p, r.spec.name);
  }
  RigSpec s = RigSpecFromParams(values);
  s.placement.seed = Seed(p);
  s.lens_residual.seed = Seed(p);
  if (!s.rig_file.empty() && fs::path(s.rig_file).is_relative()) s.rig_file = (config_dir / s.rig_file).string();
  return s;
}

void CheckCellRigFiles(const std::vector<SweepCell>& cells, const fs::path& config_dir) {
  std::set<std::string> checked;
  for (const SweepCell& cell : cells) {
    RigSpec spec;
    try {
      spec = CellRigSpec(cell.params, config_dir);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument("cell " + std::to_string(cell.index) + ": " + e.what());
    }
    if (spec.type != RigType::kFile) continue;
    if (spec.rig_file.empty()) {
      throw std::invalid_argument("cell " + std::to_string(cell.index) + ": rig file needs rig_file, the rig.json to use");
    }
    if (checked.insert(spec.rig_file).second) ReadRigFile(spec.rig_file);
  }
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
    CellRun render;
    {
      status("scene");
      const fs::path scene_file = SceneFile(p, options, status);
      const Scene& scene = cache->Get(scene_file);
      status("placing the rig");
      const RigSpec spec = CellRigSpec(p, options.config_dir);
      std::optional<PlacedRig> placed;
      try {
        placed = MakePlacedRig(spec, &scene);
      } catch (const NoRoadError& e) {
        return fail_all(p.at("scene").get<std::string>() + ": " + e.what() + "; placement road needs a scene whose road "
                        "surface is labelled road (the presets' is)");
      }
      if (!placed) return fail_all(NoPlaceMessage(spec, p.at("scene").get<std::string>()));
      const double offset_s = p.at("time_offset_ms").get<double>() / 1000.0;
      const double readout_s = p.at("readout_ms").get<double>() / 1000.0;
      for (size_t c = 0; c < placed->rig.cameras.size(); ++c) {
        placed->rig.cameras[c].time_offset_s = c * offset_s;
        placed->rig.cameras[c].readout_s = readout_s;
      }
      RenderJob job;
      job.scene = &scene;
      job.scene_name = scene_file.filename().string();
      job.rig = placed->rig;
      job.frames = placed->frames;
      job.options.samples_per_pixel = p.at("spp").get<int>();
      job.options.seed = Seed(p);
      job.options.num_threads = options.num_threads;
      job.photometric = Photometric(p);
      // The rig's own car as make-rig --ego-vehicle writes it and render reads it.
      std::optional<Scene> ego_vehicle;
      if (CellParam(p, "ego_vehicle").get<bool>()) {
        std::vector<uint8_t> glb;
        try {
          glb = EgoVehicleGlb(placed->rig, spec.placement.height_m);
        } catch (const std::invalid_argument& e) {
          return fail_all(std::string("ego_vehicle: ") + e.what());
        }
        const fs::path file = work / kEgoVehicleFile;
        std::ofstream out(file, std::ios::binary);
        out.write(reinterpret_cast<const char*>(glb.data()), std::streamsize(glb.size()));
        if (!out.flush()) throw std::runtime_error(file.string() + ": cannot write");
        out.close();
        ego_vehicle = LoadGltf(file);
        EgoVehicleToRigFrame(*ego_vehicle);
        job.ego_vehicle = &*ego_vehicle;
      }
      const SensorPreset& sensor = FindSensorPreset(p.at("sensor").get<std::string>());
      if (sensor.name != "ideal") {
        job.photometric = sensor.photometric;
        job.photometric.seed = Seed(p);
        job.defocus = sensor.defocus;
        job.jpeg_quality = sensor.jpeg_quality;
        job.sensor_preset = sensor.name;
      }
      status("rendering");
      const auto start = Clock::now();
      RenderDataset(job, dataset, false, [&](int, int) { status("rendering"); });
      render.render_time_s = Since(start);
    }
    render.overlap = ReadOverlap(DatasetLayout(dataset).OverlapJson());
    record.cell_metrics = CellMetrics(render);
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
