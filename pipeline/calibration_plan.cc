#include "pipeline/calibration_plan.h"

#include <algorithm>
#include <stdexcept>

#include "calibrator/estimators/capture_time.h"

namespace rigsim {
namespace {

// How the command line names a label source: "truth", "noisy" or the folder.
std::string LabelsName(const LabelSource& source) {
  switch (source.kind) {
    case LabelSource::Kind::kTruth: return "truth";
    case LabelSource::Kind::kNoisy: return "noisy";
    case LabelSource::Kind::kFolder: return source.folder.string();
  }
  return "";
}

// The semantic modes to run. Photos without labels (no DATASET/labels/ for the truth's labels) run
// the default modes that need none, with a warning; modes asked for by name that need labels are
// refused, saying what to do.
std::vector<SemanticMode> ModesFor(const CalibrationRequest& request, const std::function<void(const std::string&)>& warn) {
  std::vector<SemanticMode> modes = request.modes;
  const std::filesystem::path labels = DatasetLayout(request.dataset).root() / "labels";
  if (request.options.labels.kind != LabelSource::Kind::kTruth || !request.segmenter_model.empty() || std::filesystem::exists(labels) ||
      std::none_of(modes.begin(), modes.end(), NeedsLabels)) {
    return modes;
  }
  std::string needing;
  for (SemanticMode m : modes) {
    if (!NeedsLabels(m)) continue;
    if (!needing.empty()) needing += ",";
    needing += SemanticModeName(m);
  }
  if (request.modes_given || std::all_of(modes.begin(), modes.end(), NeedsLabels)) {
    throw std::runtime_error(labels.string() + ": no such folder: --semantics " + needing +
                             " needs a label image per photo (docs/calibration.md, 'Labels for the semantic modes'); for photos "
                             "without labels use --semantics none, or give labels with --labels DIR or a network with --segmenter MODEL.onnx");
  }
  warn(request.dataset.string() + " has no labels/: calibrating with --semantics none only (" + needing +
       " needs a label image per photo; --labels DIR or --segmenter MODEL.onnx gives them)");
  modes.erase(std::remove_if(modes.begin(), modes.end(), NeedsLabels), modes.end());
  return modes;
}

// The network of the request, loaded before the long run; nullptr without one or when no mode
// needs labels (with a warning).
std::shared_ptr<const Segmenter> SegmenterFor(const CalibrationRequest& request, bool labels_used,
                                              const std::function<void(const std::string&)>& warn) {
  if (request.segmenter_model.empty()) return nullptr;
  if (request.options.labels.kind != LabelSource::Kind::kTruth) {
    throw std::invalid_argument("--segmenter and --labels " + LabelsName(request.options.labels) +
                                " both say where the labels come from: give one");
  }
  if (!labels_used) {
    warn("--segmenter " + request.segmenter_model.string() + " is not used: no semantic mode given needs labels");
    return nullptr;
  }
  return std::make_shared<const Segmenter>(request.segmenter_options());
}

// --estimate-time-offsets and --rolling-shutter need frames at distinct times of a moving rig, and
// do not combine with --refine-intrinsics.
void CheckCaptureTimeOptions(const CalibrationInputs& inputs, const CalibrationRunOptions& options) {
  const CaptureTimeOptions& time = options.rig.capture_time;
  if (!time.estimate_offsets && !time.estimate_readout) return;
  const std::string flag = time.estimate_offsets ? "--estimate-time-offsets" : "--rolling-shutter";
  if (options.rig.bundle_adjustment.refine_intrinsics) {
    throw std::invalid_argument(flag + " does not combine with --refine-intrinsics: calibrate the intrinsics first, "
                                "then the capture times with them (--intrinsics)");
  }
  std::vector<double> times;
  for (const Frame& f : inputs.frames.frames) times.push_back(f.timestamp_s);
  if (const auto why = WhyNoTimingModel(times)) {
    throw std::invalid_argument(flag + ": " + DatasetLayout(inputs.dataset_dir).FramesJson().string() + ": " + *why +
                                "; capture times are estimated from a moving rig's frames and their timestamps");
  }
}

}  // namespace

LabelSource LabelSourceNamed(const std::string& labels, const SegmentationNoiseOptions& noise,
                             const std::string& noise_option_given) {
  if (labels != "noisy" && !noise_option_given.empty()) {
    throw std::invalid_argument(noise_option_given + " needs --labels noisy (got --labels " + labels + ")");
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

CalibrationPlan PlanCalibration(const CalibrationRequest& request, const std::function<void(const std::string&)>& warn) {
  CalibrationPlan plan;
  plan.dataset = request.dataset;
  plan.options = request.options;
  plan.out = request.out;
  plan.modes = ModesFor(request, warn);
  plan.labels_used = std::any_of(plan.modes.begin(), plan.modes.end(), NeedsLabels);
  plan.segmenter = SegmenterFor(request, plan.labels_used, warn);
  if (!plan.labels_used && plan.options.labels.kind != LabelSource::Kind::kTruth) {
    warn("--labels " + LabelsName(plan.options.labels) + " is not used: no semantic mode given needs labels");
  }
  CheckReplaceableOutput(plan.out);
  plan.inputs = ReadCalibrationInputs(request.dataset);
  for (const std::string& w : plan.inputs.warnings) warn(w);
  if (!request.mask_dir.empty()) {
    plan.options.masks = std::make_shared<const RigMasks>(
        ReadRigMasks(request.mask_dir, plan.inputs.rig, DatasetLayout(request.dataset).RigJson(), warn));
  }
  CheckKnownDistance(plan.inputs, plan.options);
  CheckCaptureTimeOptions(plan.inputs, plan.options);
  if (plan.segmenter) plan.photos = PhotosToSegment(request.dataset);
  plan.label_text = plan.options.labels.Describe();
  return plan;
}

SegmentDatasetSummary SegmentLabels(CalibrationPlan* plan, const std::filesystem::path& staging_dir,
                                    const std::function<void(int done, int total)>& progress) {
  if (!plan->segmenter) throw std::invalid_argument("SegmentLabels: the plan has no network");
  // The network's labels are written into the output folder and read from there.
  const std::filesystem::path segmentation = staging_dir / "segmentation";
  const SegmentDatasetSummary summary = SegmentPhotos(plan->photos, *plan->segmenter, segmentation, progress);
  plan->options.labels = LabelSource::Folder(segmentation / "labels");
  plan->label_text = "network " + plan->segmenter->options().model.string() + " (classes " + plan->segmenter->classes().name + ")";
  return summary;
}

}  // namespace rigsim
