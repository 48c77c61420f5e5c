// What `rigsim segment` and `calibrate --segmenter` share: the options of a segmentation network
// (pipeline/segmentation_run.h) and its run over a dataset's photos with a progress line.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "pipeline/segmentation_run.h"

namespace rigsim::cli {

struct SegmenterSettings {
  std::string model;  // --model (segment) or --segmenter (calibrate); empty: none given
  std::string classes = "cityscapes";
  std::string input_size;  // "WIDTHxHEIGHT", "N" (the shorter side) or empty (the model's, else 520)
  std::vector<double> mean = {0.485, 0.456, 0.406};
  std::vector<double> std = {0.229, 0.224, 0.225};
  std::string channel_order = "rgb";
  // The options other than the model's, as given on the command line (set by AddSegmenterOptions),
  // to refuse them without a model.
  std::vector<const CLI::Option*> options;

  // Throws std::invalid_argument on values that cannot be parsed (SegmenterOptions::Check does the rest).
  SegmenterOptions ToOptions() const;
  // The first option given without a model ("--classes"), or "".
  std::string GivenWithoutModel() const;
};

// --model or --segmenter (`model_option`) and --classes, --input-size, --mean, --std, --channel-order.
void AddSegmenterOptions(CLI::App& cmd, SegmenterSettings& settings, const std::string& model_option,
                         const std::string& model_help);

// Runs `segment` (a network over a dataset's photos, taking a progress callback) with a progress
// line and the time left on stderr (Ctrl-C stops after the photo being segmented), then prints what
// `segmenter` did.
SegmentDatasetSummary SegmentWithProgress(
    const Segmenter& segmenter,
    const std::function<SegmentDatasetSummary(const std::function<void(int done, int total)>& progress)>& segment);

}  // namespace rigsim::cli
