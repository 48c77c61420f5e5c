#include "pipeline/calibration_outputs.h"

#include <map>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <utility>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "dataset/image_io.h"
#include "exports/colmap.h"
#include "exports/kalibr.h"
#include "exports/opencv_yaml.h"
#include "exports/rig_plot.h"
#include "geometry/json_io.h"
#include "pipeline/calibration_json.h"
#include "pipeline/match_image.h"

namespace rigsim {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

// rig_topdown.svg: the estimate over the truth (when known), seen from above.
RigPlotInput TopDownPlot(const RigCalibrationResult& r, const std::optional<Rig>& truth, size_t cameras_exported) {
  RigPlotInput plot;
  plot.estimate = r.rig;
  plot.truth = truth;
  plot.metric = r.scale_kind == ScaleKind::kMetric;
  for (size_t c = 0; c < r.rig.cameras.size(); ++c) {
    const bool rotation_only = !r.rig.cameras[c].cam_from_rig && c < r.cam_from_rig_rotation.size();
    plot.rotation_only.push_back(rotation_only ? r.cam_from_rig_rotation[c] : std::nullopt);
  }
  plot.title = "rigsim calibrate, " + r.semantic_mode + ": " + std::to_string(cameras_exported) + " of " +
               std::to_string(r.rig.cameras.size()) + " cameras with a full pose";
  return plot;
}

// The exports of one mode's estimate (the writers of `rigsim export`) and rig_topdown.svg into
// `dir`. Returns the "outputs" record; its notes are also appended to `notes`.
Json WriteExports(const RigCalibrationResult& r, const CalibrationInputs& inputs, const fs::path& dir,
                  std::vector<std::string>* notes) {
  const ExportSelection selection = SelectExports(r, inputs.frames);
  const EstimateGauge gauge = GaugeOf(r);
  Json omitted = Json::array(), notes_json = Json::array(), colmap_frames = Json::array();
  for (const auto& [name, status] : selection.cameras_omitted) omitted.push_back({{"name", name}, {"status", status.Text()}});
  Json files = {"rig.json", "frames.json", "pairs.json"};
  auto note = [&](const std::string& text) {
    notes->push_back(r.semantic_mode + ": " + text);
    notes_json.push_back(text);
  };
  if (!selection.cameras_omitted.empty()) {
    std::string names;
    for (const auto& o : selection.cameras_omitted) names += (names.empty() ? "" : ", ") + o.first;
    note("camchain.yaml, opencv.yaml and colmap/ leave out the cameras without a full pose: " + names +
         " (see rig.json and evaluation.json for why)");
  }
  try {
    json_io::WriteTextAtomic(dir / "rig_topdown.svg",
                             RigTopDownSvg(TopDownPlot(r, inputs.truth, selection.cameras_exported.size())));
    files.push_back("rig_topdown.svg");
  } catch (const std::invalid_argument& e) {
    note(std::string("rig_topdown.svg not written: ") + e.what());
  }
  if (selection.calibrated.cameras.empty()) {
    note("no camera has a pose: no camchain.yaml, opencv.yaml or colmap/");
  } else {
    try {
      WriteKalibrCamchain(selection.calibrated, dir / "camchain.yaml", gauge);
      files.push_back("camchain.yaml");
    } catch (const std::invalid_argument& e) {  // a model Kalibr cannot express
      note(std::string("camchain.yaml not written: ") + e.what());
    }
    WriteOpenCvRigYaml(selection.calibrated, dir / "opencv.yaml", gauge);
    files.push_back("opencv.yaml");
    const DatasetLayout layout(inputs.dataset_dir);
    ColmapExportOptions colmap;
    colmap.image_name = [&layout](const std::string& cam, const std::string& frame) { return layout.ImageName(cam, frame); };
    colmap.gauge = gauge;
    WriteColmapModel(selection.calibrated, selection.colmap_frames, dir / "colmap", colmap);
    for (const Frame& f : selection.colmap_frames.frames) colmap_frames.push_back(f.name);
    files.push_back("colmap/cameras.txt");
    files.push_back("colmap/images.txt");
    files.push_back("colmap/points3D.txt");
    files.push_back("colmap/triangulate.sh");
  }
  return {{"dir", r.semantic_mode},
          {"files", files},
          {"cameras_exported", selection.cameras_exported},
          {"cameras_omitted", omitted},
          {"colmap_frames", colmap_frames},
          {"colmap_frames_omitted", selection.colmap_frames_omitted},
          {"notes", notes_json}};
}

// Photos decoded once each, on first use, however many pairs show them (Herz-Jesus-P8: 8 photos
// of 3072x2048 in 21 pairs, 42 decodes otherwise). Safe to use from several threads.
class DecodedPhotos {
 public:
  explicit DecodedPhotos(const std::vector<fs::path>& paths) {
    for (const fs::path& p : paths) {
      if (!index_.count(p)) index_.emplace(p, index_.size());
    }
    photos_ = std::vector<Photo>(index_.size());
  }
  const ImageU8& Get(const fs::path& path) {
    Photo& photo = photos_[index_.at(path)];
    std::call_once(photo.once, [&] { photo.rgb = ReadImageU8(path, 3); });
    return photo.rgb;
  }

 private:
  struct Photo {
    std::once_flag once;
    ImageU8 rgb;
  };
  std::map<fs::path, size_t> index_;
  std::vector<Photo> photos_;
};

// <mode>/matches/<cam_a>-<cam_b>.jpg: each pair's two-view inliers in its best frame, drawn over
// the two photos with the cameras' names, right and wrong by the ground truth when it is known,
// pairs in parallel (decoding the photos is most of the work).
// Returns the files written (relative to `dir`), in the pairs' order.
std::vector<std::string> WriteMatchImages(const std::vector<PairInlierSample>& samples, const CalibrationInputs& inputs,
                                          const fs::path& dir, int num_threads) {
  const DatasetLayout layout(inputs.dataset_dir);
  const FramesFile& frames = inputs.frames;
  std::vector<std::string> written(samples.size());
  std::vector<std::optional<std::pair<fs::path, fs::path>>> paths(samples.size());
  std::vector<fs::path> all_paths;
  for (size_t i = 0; i < samples.size(); ++i) {
    const PairInlierSample& s = samples[i];
    if (s.frame < 0 || size_t(s.frame) >= frames.frames.size()) continue;
    const std::string& frame = frames.frames[s.frame].name;
    const auto path_a = layout.FindImage(s.cam_a, frame), path_b = layout.FindImage(s.cam_b, frame);
    if (!path_a || !path_b) continue;
    paths[i] = {*path_a, *path_b};
    all_paths.push_back(*path_a);
    all_paths.push_back(*path_b);
  }
  DecodedPhotos photos(all_paths);
  fs::create_directories(dir / "matches");
  tbb::task_arena arena(num_threads > 0 ? num_threads : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(size_t(0), samples.size(), [&](size_t i) {
      if (!paths[i]) return;
      const PairInlierSample& s = samples[i];
      const std::string name = "matches/" + s.cam_a + "-" + s.cam_b + ".jpg";
      const MatchAnnotation note{s.cam_a, s.cam_b, s.correct};
      WriteImage(dir / name, DrawMatches(photos.Get(paths[i]->first), photos.Get(paths[i]->second), s.points, {}, note));
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

std::optional<Rigid3d> EstimatedRigFromWorld(const RigCalibrationResult& r, size_t frame) {
  if (frame < r.rig_from_world.size()) return r.rig_from_world[frame];
  if (frame == 0) return Rigid3d();  // without positions only frame 0 has a pose: its rig frame is the world
  return std::nullopt;
}

ExportSelection SelectExports(const RigCalibrationResult& r, const FramesFile& frames) {
  ExportSelection out;
  out.calibrated = r.rig.PosedCameras();
  for (size_t c = 0; c < r.rig.cameras.size(); ++c) {
    const RigCamera& rc = r.rig.cameras[c];
    if (rc.cam_from_rig) {
      out.cameras_exported.push_back(rc.name);
    } else {
      out.cameras_omitted.emplace_back(rc.name, c < r.camera_status.size() ? r.camera_status[c] : CameraStatus{});
    }
  }
  for (size_t k = 0; k < frames.frames.size(); ++k) {
    const Frame& f = frames.frames[k];
    const std::optional<Rigid3d> rig_from_world = EstimatedRigFromWorld(r, k);
    if (rig_from_world) {
      out.colmap_frames.frames.push_back(Frame{f.name, rig_from_world, f.timestamp_s});
    } else {
      out.colmap_frames_omitted.push_back(f.name);
    }
  }
  return out;
}

EstimateGauge GaugeOf(const RigCalibrationResult& r) {
  EstimateGauge g;
  g.rig_frame = r.rig.cameras.empty() ? "" : r.rig.cameras[0].name;
  g.scale = r.scale;
  g.metric = r.scale_kind == ScaleKind::kMetric;
  g.frames = "frames.json";
  return g;
}

Rig EstimatedRig(const RigCalibrationResult& r) {
  Rig rig = r.rig;
  for (size_t c = 0; c < rig.cameras.size() && c < r.camera_status.size(); ++c) {
    if (r.camera_status[c].outcome != CameraOutcome::kUnsynchronised) continue;
    const RigCameraStats& measured = r.camera_stats[c];
    if (measured.time_offset_s) rig.cameras[c].time_offset_s = *measured.time_offset_s;
  }
  return rig;
}

FramesFile EstimatedFrames(const RigCalibrationResult& r, const FramesFile& frames) {
  FramesFile out = frames;
  for (size_t k = 0; k < out.frames.size(); ++k) out.frames[k].rig_from_world = EstimatedRigFromWorld(r, k);
  return out;
}

std::vector<std::string> WriteCalibrationResults(const CalibrationRun& run, const std::filesystem::path& dir) {
  std::vector<std::string> notes;
  Json evaluation = EvaluationJson(run);
  evaluation["label_source"] = LabelSourceJson(run.options.labels, run.labels_used);
  for (size_t m = 0; m < run.results.size(); ++m) {
    const RigCalibrationResult& r = run.results[m];
    const fs::path mode_dir = dir / r.semantic_mode;
    fs::create_directories(mode_dir);
    WriteEstimateRig(EstimatedRig(r), GaugeOf(r), mode_dir / "rig.json");
    WriteFrames(EstimatedFrames(r, run.inputs.frames), mode_dir / "frames.json");
    Json pairs = PairsJson(run, m, evaluation["label_source"]);
    if (evaluation.contains("masks")) pairs["masks"] = evaluation["masks"]["folder"];
    json_io::WriteTextAtomic(mode_dir / "pairs.json", pairs.dump(2) + "\n");
    Json& outputs = evaluation["methods"][r.semantic_mode]["outputs"];
    outputs = WriteExports(r, run.inputs, mode_dir, &notes);
    for (const std::string& file :
         WriteMatchImages(run.records.at(m).inlier_samples, run.inputs, mode_dir, run.options.rig.pairwise.num_threads)) {
      outputs["files"].push_back(file);
    }
  }
  json_io::WriteTextAtomic(dir / "evaluation.json", evaluation.dump(2) + "\n");
  return notes;
}

}  // namespace rigsim
