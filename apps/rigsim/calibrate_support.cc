#include "apps/rigsim/calibrate_support.h"

#include <cmath>
#include <cstdio>
#include <functional>

#include "apps/rigsim/commands.h"
#include "apps/rigsim/parse_errors.h"
#include "apps/rigsim/progress.h"
#include "common/format.h"
#include "dataset/dataset.h"
#include "dataset/output_folder.h"
#include "pipeline/calibration_outputs.h"
#include "pipeline/calibration_plan.h"
#include "pipeline/report_table.h"

namespace rigsim::cli {

LabelSource LabelSettings::ToSource() const {
  std::string noise_option_given;
  for (const CLI::Option* opt : noise_options) {
    if (opt->count() > 0 && noise_option_given.empty()) noise_option_given = opt->get_name();
  }
  return LabelSourceNamed(labels, noise, noise_option_given);
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

CalibrationRunOptions CalibrateSettings::ToOptions() const {
  CalibrationRunOptions o = options;
  o.labels = labels.ToSource();
  if (const std::string option = segmenter.GivenWithoutModel(); !option.empty()) {
    throw std::invalid_argument(option + " needs --segmenter MODEL.onnx");
  }
  if (!reliable.empty()) {
    try {
      o.reliable = ReliableClasses::FromNames(reliable);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string("--reliable: ") + e.what());
    }
  }
  if (!known_distance.empty()) {
    if (known_distance.size() != 3) throw std::invalid_argument("--known-distance takes CAM_A CAM_B METRES");
    double metres = 0.0;
    try {
      metres = std::stod(known_distance[2]);
    } catch (const std::exception&) {
      throw std::invalid_argument("--known-distance: '" + known_distance[2] + "' is not a number of metres");
    }
    if (!std::isfinite(metres) || !(metres > 0)) {
      throw std::invalid_argument("--known-distance: the distance must be more than 0 metres (got " + known_distance[2] + ")");
    }
    if (known_distance[0] == known_distance[1]) {
      throw std::invalid_argument("--known-distance: give two different cameras (got '" + known_distance[0] + "' twice)");
    }
    o.rig.known_distance = KnownDistance{known_distance[0], known_distance[1], metres};
  }
  if (!intrinsics.empty()) o.intrinsics = CalibrationRunOptions::GivenIntrinsics{ReadRig(intrinsics), intrinsics};
  if (!intrinsics_sd.empty()) {
    if (o.rig.bundle_adjustment.refine_intrinsics) {
      throw std::invalid_argument("--intrinsics-sd is for intrinsics held at the given values; --refine-intrinsics "
                                  "refines them instead: give one or the other");
    }
    if (o.rig.capture_time.estimate_offsets || o.rig.capture_time.estimate_readout) {
      throw std::invalid_argument(
          "--intrinsics-sd does not combine with --estimate-time-offsets or --rolling-shutter");
    }
    o.rig.bundle_adjustment.given_intrinsics_sd = ParseIntrinsicsSd(intrinsics_sd);
  }
  o.Check();
  return o;
}

GivenIntrinsicsDeviation ParseIntrinsicsSd(const std::string& text) {
  const std::string usage = "give F,P: the focal lengths' standard deviation as a fraction (0.002 is 0.2 %) and the "
                            "principal point's in pixels (got " + text + ")";
  const std::optional<std::array<double, 2>> values = NumberPair(text);
  if (!values) throw std::invalid_argument(usage);
  GivenIntrinsicsDeviation sd;
  sd.focal_fraction = (*values)[0];
  sd.principal_point_px = (*values)[1];
  if (!(sd.focal_fraction >= 0 && sd.focal_fraction < 0.5)) {
    throw std::invalid_argument("F, the focal lengths' standard deviation as a fraction, must be 0 or more and below "
                                "0.5 (got " + text.substr(0, text.find(',')) + " in " + text + ")");
  }
  if (!(sd.principal_point_px >= 0)) {
    throw std::invalid_argument("P, the principal point's standard deviation in pixels, must be 0 or more (got " +
                                text.substr(text.find(',') + 1) + " in " + text + ")");
  }
  return sd;
}

std::vector<SemanticMode> CalibrateSettings::Modes() const {
  std::vector<SemanticMode> modes;
  for (const std::string& s : semantics) {
    try {
      modes.push_back(SemanticModeFromName(s));
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string("--semantics: ") + e.what());
    }
  }
  if (modes.empty()) throw std::invalid_argument("--semantics: give at least one mode");
  return modes;
}

void AddCalibrateSettingsOptions(CLI::App& cmd, CalibrateSettings& s) {
  s.semantics_option = cmd.add_option("--semantics", s.semantics,
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
  cmd.add_option("--intrinsics", s.intrinsics,
                 "FILE: a rig.json whose cameras' intrinsics (model, params; matched by name, same image\n"
                 "size) are calibrated with instead of DATASET/rig.json's, e.g. a datasheet's. The dataset's\n"
                 "stay the truth a rendered dataset is compared with")
      ->check(CLI::ExistingFile);
  IntrinsicsErrorOptions& error = s.options.intrinsics_error;
  cmd.add_option("--intrinsics-error", error.error,
                 "E: calibrate with intrinsics as a user has them, off the given ones (rig.json's or\n"
                 "--intrinsics') by a seeded error of relative size E (0.01 is 1 %): each camera's focal\n"
                 "lengths multiplied by exp(E z), its principal point moved by E z times half the image's\n"
                 "width and height (px), each distortion coefficient multiplied by 1 + E z, every z a\n"
                 "standard normal draw of (--intrinsics-error-seed, camera index, parameter). The dataset's\n"
                 "rig.json stays the truth; evaluation.json's intrinsics_error has each camera's given and\n"
                 "true fx, fy, cx, cy. 0 to " + Fixed(IntrinsicsErrorOptions::kMaxError, 1) + "; 0: none")
      ->capture_default_str()
      ->check(CLI::Validator(
          [](std::string& input) -> std::string {
            double v = 0;
            if (!CLI::detail::lexical_cast(input, v) || !std::isfinite(v) || v < 0 || v > IntrinsicsErrorOptions::kMaxError) {
              return "must be 0 to " + Fixed(IntrinsicsErrorOptions::kMaxError, 1) + ", a fraction (0.01 is 1 %) (got " + input + ")";
            }
            return "";
          },
          "0 to " + Fixed(IntrinsicsErrorOptions::kMaxError, 1)));
  cmd.add_option("--intrinsics-error-seed", error.seed,
                 "seed of --intrinsics-error's draws; each camera's depend only on (seed, camera index)")
      ->capture_default_str();
  cmd.add_option("--intrinsics-sd", s.intrinsics_sd,
                 "F,P: how uncertain the given intrinsics are, as an intrinsic calibration reports it (OpenCV's\n"
                 "stdDeviationsIntrinsics, Kalibr's): F the standard deviation of the focal lengths as a fraction\n"
                 "(0.002 is 0.2 %), P that of the principal point in pixels, for fx, fy, cx, cy of every camera,\n"
                 "each independently; the distortion counts as exact. The poses do not change (the intrinsics\n"
                 "stay held at the given values); only their stated deviations grow by what that uncertainty\n"
                 "moves them, so that they cover it. Not with --refine-intrinsics nor the capture-time options")
      ->type_name("F,P")
      ->check(CLI::Validator(
          [](std::string& input) -> std::string {
            try {
              ParseIntrinsicsSd(input);
            } catch (const std::invalid_argument& e) {
              return e.what();
            }
            return "";
          },
          ""));
  const IntrinsicsPriorOptions priors;
  cmd.add_flag("--refine-intrinsics", s.options.rig.bundle_adjustment.refine_intrinsics,
               "refine every camera's intrinsics (focal lengths, principal point, distortion) in the\n"
               "bundle adjustment, after the poses are found with the given ones, under Gaussian priors\n"
               "on the given values: sigma " + Fixed(100 * priors.focal_fraction, 0) + "% of the focal length (fx - fy: " +
                   Fixed(100 * priors.aspect_fraction, 1) + "%), " + Fixed(100 * priors.principal_point_fraction, 1) +
                   "% of the image's larger side for\n"
               "the principal point, " + Fixed(priors.first_radial, 2) + " for k1, " + Fixed(priors.higher_radial, 2) +
                   " for further radial and " + Fixed(priors.tangential, 3) + " for tangential terms. <mode>/rig.json\n"
               "gets the refined intrinsics; evaluation.json has the given and refined values and their\n"
               "standard deviations (and errors against the truth for a rendered dataset)");
  CaptureTimeOptions& time = s.options.rig.capture_time;
  cmd.add_flag("--estimate-time-offsets", time.estimate_offsets,
               "the cameras are not synchronised: estimate each camera's capture time relative to the\n"
               "first camera's in the bundle adjustment (needs 3 or more frames of a moving rig with\n"
               "distinct timestamp_s in frames.json, and a path whose turn rate or speed changes). Without\n"
               "it a camera the images show capturing at another time than the first is not calibrated");
  cmd.add_flag("--rolling-shutter", time.estimate_readout,
               "estimate each camera's rolling-shutter readout time (first row to last) in the bundle\n"
               "adjustment; rig.json's readout_direction gives the order of the rows");
  FeatureOptions& features = s.options.features;
  cmd.add_option("--max-features", features.max_features, "strongest keypoints kept per image (every --features type)")
      ->capture_default_str()
      ->check(Positive());
  cmd.add_option("--sift-contrast", features.contrast_threshold,
                 "SIFT contrast threshold; lower finds more, weaker keypoints")
      ->capture_default_str()
      ->check(Positive());
  cmd.add_option("--screen-features", s.options.rig.pairwise.screen_features,
                 "pair screening: match only this many strongest keypoints of two frames first and\n"
                 "skip the full matching of pairs that show no shared view; 0 matches every pair in full")
      ->capture_default_str()
      ->check(NonNegative());
  cmd.add_option("--ratio", s.options.rig.pairwise.matching.ratio,
                 "Lowe's ratio test: keep a match when best < ratio x second best")
      ->capture_default_str()
      ->check(CLI::Range(0.1, 1.0));
  cmd.add_option("--max-error-px", s.options.rig.pairwise.two_view.max_error_px,
                 "inlier threshold of the robust relative-pose fit (px)")
      ->capture_default_str()
      ->check(Positive());
  if (cmd.get_option_no_throw("--threads") == nullptr) {
    cmd.add_option("--threads", s.options.rig.pairwise.num_threads, "worker threads, 0 = all cores")
        ->capture_default_str()
        ->check(NonNegative());
  }
}

void AddMaskOption(CLI::App& cmd, CalibrateSettings& s) {
  cmd.add_option("--mask", s.mask,
                 "hide what moves with the rig, its own vehicle (hood, body, mounts): DIR/<camera>.png\n"
                 "per camera, the camera's image size, applied to every frame in every semantic mode; no\n"
                 "feature is kept where the mask is black (0), anything else is used (COLMAP's convention;\n"
                 "grey or RGB(A), alpha ignored). A camera without a mask is not masked (with a warning).\n"
                 "evaluation.json's masks says what each mask hid and how many keypoints it removed")
      ->type_name("DIR");
}

OutputFolderRequest CalibrationOutputFolder(const std::filesystem::path& dataset, const CalibrateSettings& settings,
                                            const std::filesystem::path& out_dir, bool force) {
  const DatasetLayout layout(dataset);
  const bool default_folder = out_dir.lexically_normal() == (dataset / "calibration").lexically_normal();
  OutputFolderRequest out{out_dir, default_folder ? "" : "--out", "rigsim calibrate", {}, force};
  out.inputs = {{layout.RigJson(), "the dataset's rig.json"},
                {layout.FramesJson(), "the dataset's frames.json"},
                {layout.OverlapJson(), "the dataset's overlap.json"},
                {layout.root() / "images", "the dataset's images/"},
                {layout.root() / "labels", "the dataset's labels/"},
                {layout.root() / "depth", "the dataset's depth/"}};
  if (!settings.intrinsics.empty()) out.inputs.push_back({settings.intrinsics, "--intrinsics"});
  const std::string& labels = settings.labels.labels;
  if (labels != "truth" && labels != "noisy" && !labels.empty()) out.inputs.push_back({labels, "--labels"});
  if (!settings.segmenter.model.empty()) out.inputs.push_back({settings.segmenter.model, "--segmenter"});
  if (!settings.mask.empty()) out.inputs.push_back({settings.mask, "--mask"});
  return out;
}

void Warn(const std::string& warning) { std::fprintf(stderr, "warning: %s\n", warning.c_str()); }

CalibrationRun CalibrateShowingStages(CalibrationPlan& plan) {
  StageLine stages;
  plan.options.rig.progress = [&stages](const std::string& stage) { stages(stage); };
  CalibrationRun run;
  try {
    run = CalibrateDataset(plan);
  } catch (...) {
    plan.options.rig.progress = nullptr;
    stages.Finish();  // the error starts a line of its own
    throw;
  }
  plan.options.rig.progress = run.options.rig.progress = nullptr;  // they told `stages`, which ends here
  stages.Finish();
  return run;
}

CalibrationRun CalibrateAndReport(const std::filesystem::path& dataset, const CalibrateSettings& settings,
                                  const std::filesystem::path& out_dir, bool force) {
  CalibrationRequest request;
  request.dataset = dataset;
  request.options = settings.ToOptions();
  request.modes = settings.Modes();
  request.modes_given = settings.semantics_option != nullptr && settings.semantics_option->count() > 0;
  request.segmenter_model = settings.segmenter.model;
  request.segmenter_options = [&settings] { return settings.segmenter.ToOptions(); };
  request.out = CalibrationOutputFolder(dataset, settings, out_dir, force);
  request.mask_dir = settings.mask;
  CalibrationPlan plan = PlanCalibration(request, Warn);
  StagedOutput staged(plan.out);
  if (plan.segmenter) {
    SegmentWithProgress(*plan.segmenter, [&](const std::function<void(int, int)>& progress) {
      return SegmentLabels(&plan, staged.staging_dir(), progress);
    });
  }
  const std::string masks_text =
      plan.options.masks ? DescribeRigMasks(*plan.options.masks, plan.inputs.rig.cameras.size()) : "";
  std::fprintf(stderr, "calibrating %s (%s%s%s)...\n", dataset.string().c_str(), Count(plan.modes.size(), "semantic mode").c_str(),
               plan.labels_used ? (", labels: " + plan.label_text).c_str() : "",
               masks_text.empty() ? "" : (", masks: " + masks_text).c_str());
  CalibrationRun run = CalibrateShowingStages(plan);
  for (const std::string& note : WriteCalibrationResults(run, staged.staging_dir())) Warn(note);
  staged.Commit();

  const CalibrationInputs& inputs = plan.inputs;
  const std::vector<RigCalibrationResult>& results = run.results;
  std::printf("\nRelative pose of every camera pair (matches of %s pooled):\n\n",
              Count(results.empty() ? 0 : results[0].pairwise.num_frames, "frame").c_str());
  std::printf("%s\n", FormatPairTable(run).c_str());
  std::printf("%s\n", FormatSummary(run).c_str());
  std::printf("Rig: every camera's pose (gauge: %s is the rig frame; errors after aligning it):\n\n",
              results.empty() || results[0].rig.cameras.empty() ? "camera 0" : results[0].rig.cameras[0].name.c_str());
  std::printf("%s\n", FormatRigTable(run).c_str());
  std::printf("%s", FormatRigSummary(run).c_str());
  if (const std::string times = FormatTimeTable(run); !times.empty()) {
    std::printf("\nCapture times: each camera's offset from %s's (positive: it captures later) and its rolling-shutter "
                "readout, +- one standard deviation%s:\n\n%s",
                results[0].rig.cameras[0].name.c_str(), inputs.truth ? "; error against the truth" : "", times.c_str());
  }
  if (const IntrinsicsErrorOptions& e = plan.options.intrinsics_error; e.Enabled()) {
    std::printf("\nIntrinsics given with an error of %s (seed %llu): see intrinsics_error in evaluation.json\n",
                (Fixed(100 * e.error, 1) + " %").c_str(), static_cast<unsigned long long>(e.seed));
  }
  if (const auto& sd = plan.options.rig.bundle_adjustment.given_intrinsics_sd) {
    std::printf("\nStated deviations include the given intrinsics' own: focal lengths +- %s, principal point +- %s px "
                "(--intrinsics-sd; the poses placed are as without it)\n",
                (Fixed(100 * sd->focal_fraction, 2) + " %").c_str(), Fixed(sd->principal_point_px, 2).c_str());
  }
  if (plan.options.rig.bundle_adjustment.refine_intrinsics) {
    std::printf("\nIntrinsics refined in the bundle adjustment (change from the given values, +- one standard "
                "deviation%s):\n\n%s\n",
                inputs.truth ? "; error against the truth" : "", FormatIntrinsicsTable(run).c_str());
  }
  std::printf("calibration took %.1f s; labels: %s%s; results in %s:\n", run.seconds,
              plan.labels_used ? plan.label_text.c_str() : "not used",
              masks_text.empty() ? "" : ("; masks: " + masks_text).c_str(), out_dir.string().c_str());
  if (plan.segmenter) std::printf("  segmentation/: the network's labels/, labels_color/ and segmentation.json\n");
  std::printf("  evaluation.json; per mode <mode>/: rig.json and frames.json (the estimate and its rig poses), camchain.yaml\n"
              "  (Kalibr), opencv.yaml, colmap/, pairs.json,\n"
              "  rig_topdown.svg (the rig seen from above%s), matches/ (each solved pair's inliers)\n",
              results.empty() || !inputs.truth ? "" : ", against the truth");
  return run;
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
