#include "pipeline/calibration_run.h"

#include <algorithm>
#include <chrono>
#include <functional>
#include <stdexcept>
#include <string>

#include <tbb/parallel_for.h>

#include "calibrator/features/parallel_scope.h"
#include "common/did_you_mean.h"
#include "dataset/capture_poses.h"
#include "dataset/image_io.h"
#include "geometry/camera_validation.h"
#include "geometry/json_io.h"
#include "pipeline/calibration_plan.h"
#include "pipeline/feature_cache.h"

namespace rigsim {
namespace {

// The rig the calibration uses (CalibratorRig).
// Checks what the options do not decide: two cameras or more, given intrinsics for every camera at
// its size, some frames.
Rig CalibrationRig(const CalibrationInputs& inputs, const CalibrationRunOptions& options) {
  const std::filesystem::path rig_json = DatasetLayout(inputs.dataset_dir).RigJson();
  const Rig rig = CalibratorRig(inputs, options);
  if (rig.cameras.size() < 2) throw std::runtime_error(rig_json.string() + ": calibration needs at least 2 cameras");
  if (inputs.frames.frames.empty()) throw std::runtime_error(inputs.dataset_dir.string() + ": no frames found");
  return rig;
}

// Every photo (camera-major: camera * frames + frame), checked to be there and of its camera's
// size from the file headers before any is decoded: a missing or wrong photo stops the run at
// once, not after minutes of detection.
std::vector<std::filesystem::path> CheckPhotos(const CalibrationInputs& inputs, const Rig& rig) {
  const DatasetLayout layout(inputs.dataset_dir);
  std::vector<std::filesystem::path> paths;
  for (const RigCamera& rc : rig.cameras) {
    for (const Frame& frame : inputs.frames.frames) {
      const std::filesystem::path path = layout.RequireImage(rc.name, frame.name);
      const ImageSize size = ReadImageSize(path);
      const int w = rc.camera.width(), h = rc.camera.height();
      if (size.width != w || size.height != h) {
        throw std::runtime_error(path.string() + ": image is " + std::to_string(size.width) + "x" +
                                 std::to_string(size.height) + ", camera '" + rc.name + "' is " + std::to_string(w) +
                                 "x" + std::to_string(h));
      }
      paths.push_back(path);
    }
  }
  return paths;
}

// Each pair's inliers in its best frame (the most inliers; the first of equals).
std::vector<PairInlierSample> InlierSamples(const Rig& rig, const CalibrationReport& report,
                                            const PairwiseMatchData& data) {
  std::vector<PairInlierSample> samples;
  for (size_t p = 0; p < report.pairs.size() && p < data.inliers.size(); ++p) {
    const auto& per_frame = data.inliers[p];
    size_t best = 0;
    for (size_t k = 1; k < per_frame.size(); ++k) {
      if (per_frame[k].size() > per_frame[best].size()) best = k;
    }
    if (per_frame.empty() || per_frame[best].empty()) continue;
    const int a = rig.FindCamera(report.pairs[p].cam_a), b = rig.FindCamera(report.pairs[p].cam_b);
    if (a < 0 || b < 0 || best >= data.keypoints.size()) continue;
    PairInlierSample s{static_cast<int>(p), report.pairs[p].cam_a, report.pairs[p].cam_b, int(best), {}, {}};
    for (const auto& [ka, kb] : per_frame[best]) {
      s.points.emplace_back(data.keypoints[best][a].at(ka), data.keypoints[best][b].at(kb));
    }
    samples.push_back(std::move(s));
  }
  return samples;
}

}  // namespace

OverlapTable ReadOverlap(const std::filesystem::path& overlap_json) {
  OverlapTable table;
  if (!std::filesystem::exists(overlap_json)) return table;
  const json_io::Json j = json_io::ReadFile(overlap_json);
  if (!j.contains("pairs") || !j["pairs"].is_array()) {
    throw std::runtime_error(overlap_json.string() + ": expected a 'pairs' array");
  }
  for (const auto& p : j["pairs"]) {
    const std::string src = overlap_json.string();
    const auto a = json_io::Get<std::string>(p, "a", src, "pairs[]");
    const auto b = json_io::Get<std::string>(p, "b", src, "pairs[]");
    const double ab = json_io::Get<double>(p, "overlap_a_in_b", src, "pairs[]");
    const double ba = json_io::Get<double>(p, "overlap_b_in_a", src, "pairs[]");
    table[{a, b}] = table[{b, a}] = std::min(ab, ba);
  }
  return table;
}

CalibrationInputs ReadCalibrationInputs(const std::filesystem::path& dataset_dir) {
  const DatasetLayout layout(dataset_dir);
  CalibrationInputs in;
  in.dataset_dir = dataset_dir;
  in.overlap = ReadOverlap(layout.OverlapJson());
  in.rig = ReadRig(layout.RigJson());
  in.warnings = CheckRigCoversImages(in.rig, layout.RigJson().string());
  const size_t posed = in.rig.PosedCameras().cameras.size();
  if (posed > 0 && posed < in.rig.cameras.size()) {
    in.warnings.push_back(layout.RigJson().string() + ": cam_from_rig given for " + std::to_string(posed) + " of " +
                          std::to_string(in.rig.cameras.size()) + " cameras (not for " + CamerasWithoutPose(in.rig) +
                          "): the estimate is not compared with the truth, which needs every camera's");
  }
  if (in.rig.HasAllPoses()) in.truth = in.rig;
  if (!in.rig.cameras.empty()) in.frames = layout.ReadFramesOrScan(in.rig.cameras[0].name);
  // The truth of a camera that captures between frames needs the rig's path: checked before the
  // run, naming the file, rather than when the estimate is scored.
  if (in.truth && std::filesystem::exists(layout.FramesJson())) CapturePoses(in.rig.cameras, in.frames, layout.FramesJson().string());
  return in;
}

void CalibrationRunOptions::Check() const {
  rig.Check();
  features.Check();
  precision.Check();
  labels.Check();
  intrinsics_error.Check();
}

Rig WithGivenIntrinsics(const Rig& rig, const Rig& intrinsics, const std::string& source) {
  Rig out = rig;
  for (RigCamera& rc : out.cameras) {
    const int i = intrinsics.FindCamera(rc.name);
    if (i < 0) {
      std::string names;
      for (const RigCamera& c : intrinsics.cameras) names += (names.empty() ? "" : ", ") + c.name;
      throw std::invalid_argument(source + ": no camera '" + rc.name + "' (it has " + (names.empty() ? "none" : names) +
                                  "); give the intrinsics of every camera of the dataset");
    }
    const Camera& given = intrinsics.cameras[i].camera;
    if (given.width() != rc.camera.width() || given.height() != rc.camera.height()) {
      throw std::invalid_argument(source + ": camera '" + rc.name + "' is " + std::to_string(given.width()) + "x" +
                                  std::to_string(given.height()) + ", the dataset's photos are " +
                                  std::to_string(rc.camera.width()) + "x" + std::to_string(rc.camera.height()));
    }
    rc.camera = given;
  }
  return out;
}

Rig CalibratorRig(const CalibrationInputs& inputs, const CalibrationRunOptions& options) {
  const Rig given =
      options.intrinsics ? WithGivenIntrinsics(inputs.rig, options.intrinsics->rig, options.intrinsics->source) : inputs.rig;
  return WithIntrinsicsError(given, options.intrinsics_error);
}

namespace {

// CalibrateDataset once the known distance is checked against the inputs (CheckKnownDistance).
CalibrationRun CalibrateChecked(const CalibrationInputs& inputs, const CalibrationRunOptions& options,
                                const std::vector<SemanticMode>& modes) {
  const auto start = std::chrono::steady_clock::now();
  CalibrationRun run;
  run.inputs = inputs;
  run.options = options;
  run.modes = modes;
  run.labels_used = std::any_of(modes.begin(), modes.end(), NeedsLabels);
  const Rig rig = CalibrationRig(inputs, options);
  const std::vector<std::filesystem::path> photos = CheckPhotos(inputs, rig);
  const int num_threads = options.rig.pairwise.num_threads;
  const ParallelScope parallel(num_threads);
  const std::string detecting = "detecting keypoints in " + std::to_string(photos.size()) + " photos";
  options.rig.Tell(detecting);
  // A line at each quarter done: detection is the longest stage of a run over many photos.
  const int num_photos = static_cast<int>(photos.size());
  int quarter_told = 0;
  const auto photos_done = [&](int done) {
    if (done == num_photos || done * 4 / num_photos <= quarter_told) return;
    quarter_told = done * 4 / num_photos;
    options.rig.Tell(detecting + ": " + std::to_string(done) + " done");
  };
  const FeatureCache features(DatasetLayout(inputs.dataset_dir), rig, inputs.frames, photos, modes, options.features,
                              options.reliable.Ids(), options.labels, num_threads, options.masks.get(),
                              options.rig.progress ? photos_done : std::function<void(int)>());

  // The modes side by side: each one's stages run in parallel too, and a mode's result does not
  // depend on the others'.
  const size_t n = modes.size();
  run.results.resize(n);
  run.records.resize(n);
  std::vector<PairwiseMatchData> matches(n);
  tbb::parallel_for(size_t(0), n, [&](size_t m) {
    RigViews views;
    for (const RigCamera& rc : rig.cameras) {
      views.camera_names.push_back(rc.name);
      views.cameras.push_back(rc.camera);
    }
    views.num_frames = static_cast<int>(inputs.frames.frames.size());
    views.features = features.Of(modes[m]);
    for (const Frame& frame : inputs.frames.frames) views.frame_times_s.push_back(frame.timestamp_s);
    for (const RigCamera& rc : rig.cameras) views.readout_bottom_to_top.push_back(rc.readout_bottom_to_top);
    RigCalibrationOptions o = options.rig;
    o.pairwise.matching.gate_by_class = UsesGating(modes[m]);
    if (options.rig.progress) {
      const std::string mode(SemanticModeName(modes[m]));
      o.progress = [tell = options.rig.progress, mode](const std::string& stage) { tell(mode + ": " + stage); };
    }
    RigCalibrationResult& r = run.results[m];
    // The matches are kept to be scored against the truth and drawn.
    r = CalibrateRig(views, o, &matches[m]);
    r.semantic_mode = std::string(SemanticModeName(modes[m]));
    run.records[m].detect_time_s = features.DetectTimeS(modes[m]);
    if (options.masks) run.records[m].removed_by_mask = features.RemovedByMask(modes[m]);
    run.records[m].inlier_samples = InlierSamples(inputs.rig, r.pairwise, matches[m]);
  });

  if (options.evaluate && inputs.truth) {
    std::vector<CalibrationScores> scores;
    for (const RigCalibrationResult& r : run.results) scores.push_back(ScorePoses(*inputs.truth, inputs.frames, r));
    ScoreMatches(inputs.dataset_dir, *inputs.truth, inputs.frames, run.results, matches, options.precision, &scores);
    for (size_t m = 0; m < n; ++m) {
      for (PairInlierSample& s : run.records[m].inlier_samples) s.correct = InlierVerdicts(scores[m], matches[m], s.pair, s.frame);
      run.records[m].truth = std::move(scores[m]);
    }
  }
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return run;
}

}  // namespace

void CheckKnownDistance(const CalibrationInputs& inputs, const CalibrationRunOptions& options) {
  if (!options.rig.known_distance) return;
  std::vector<std::string> names;
  for (const RigCamera& c : inputs.rig.cameras) names.push_back(c.name);
  for (const std::string& name : {options.rig.known_distance->cam_a, options.rig.known_distance->cam_b}) {
    if (inputs.rig.FindCamera(name) >= 0) continue;
    std::string list;
    for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
    throw std::invalid_argument("--known-distance: no camera '" + name + "' in " +
                                DatasetLayout(inputs.dataset_dir).RigJson().string() + DidYouMean(name, names) +
                                "; its cameras are " + list);
  }
}

CalibrationRun CalibrateDataset(const CalibrationInputs& inputs, const CalibrationRunOptions& options,
                                const std::vector<SemanticMode>& modes) {
  if (modes.empty()) throw std::invalid_argument("CalibrateDataset: no semantic mode given");
  options.Check();
  CheckKnownDistance(inputs, options);
  return CalibrateChecked(inputs, options, modes);
}

CalibrationRun CalibrateDataset(const CalibrationPlan& plan) {
  if (plan.modes.empty()) throw std::invalid_argument("CalibrateDataset: no semantic mode given");
  plan.options.Check();
  CalibrationRun run = CalibrateChecked(plan.inputs, plan.options, plan.modes);
  if (plan.segmenter) run.options.labels.folder = plan.out.dir / "segmentation" / "labels";
  return run;
}

CalibrationRun CalibrateDataset(const std::filesystem::path& dataset_dir, const CalibrationRunOptions& options,
                                const std::vector<SemanticMode>& modes) {
  return CalibrateDataset(ReadCalibrationInputs(dataset_dir), options, modes);
}

std::string CamerasWithoutPose(const Rig& rig) {
  std::string names;
  for (const RigCamera& rc : rig.cameras) {
    if (!rc.cam_from_rig) names += (names.empty() ? "" : ", ") + rc.name;
  }
  return names;
}

}  // namespace rigsim
