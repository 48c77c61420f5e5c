#include "apps/rigsim/segment_support.h"

#include <chrono>
#include <cstdio>
#include <stdexcept>

#include "apps/rigsim/interrupt.h"
#include "apps/rigsim/progress.h"
#include "common/format.h"

namespace rigsim::cli {
namespace {

std::array<double, 3> Three(const std::vector<double>& v, const char* option) {
  if (v.size() != 3) {
    throw std::invalid_argument(std::string(option) + ": give three values, one per input channel (got " +
                                std::to_string(v.size()) + ")");
  }
  return {v[0], v[1], v[2]};
}

}  // namespace

SegmenterOptions SegmenterSettings::ToOptions() const {
  SegmenterOptions o;
  o.model = model;
  o.classes = classes;
  if (!input_size.empty()) {
    int w = 0, h = 0, n = 0;
    char x = 0, rest = 0;
    if (std::sscanf(input_size.c_str(), "%d%c%d%c", &w, &x, &h, &rest) == 3 && (x == 'x' || x == 'X')) {
      o.input_width = w;
      o.input_height = h;
      if (w <= 0 || h <= 0) throw std::invalid_argument("--input-size: both sides must be above 0 (got " + input_size + ")");
    } else if (std::sscanf(input_size.c_str(), "%d%c", &n, &rest) == 1 && n > 0) {
      o.shorter_side = n;
    } else {
      throw std::invalid_argument("--input-size: give WIDTHxHEIGHT (520x520) or the shorter side in px (520), got '" +
                                  input_size + "'");
    }
  }
  o.mean = Three(mean, "--mean");
  o.std = Three(std, "--std");
  o.channel_order = channel_order == "bgr" ? ChannelOrder::kBgr : ChannelOrder::kRgb;
  o.Check();
  return o;
}

std::string SegmenterSettings::GivenWithoutModel() const {
  if (!model.empty()) return "";
  for (const CLI::Option* opt : options) {
    if (opt->count() > 0) return opt->get_name();
  }
  return "";
}

void AddSegmenterOptions(CLI::App& cmd, SegmenterSettings& s, const std::string& model_option,
                         const std::string& model_help) {
  CLI::Option* model = cmd.add_option(model_option, s.model, model_help);
  if (model_option == "--model") model->required();
  const std::string needs = model_option == "--model" ? "" : " (with " + model_option + ")";
  s.options.push_back(cmd.add_option("--classes", s.classes,
                                     "what the network's output channels are" + needs +
                                         ": cityscapes (19 training classes),\n"
                                         "ade20k (150 classes), voc (21, torchvision's pretrained models) or a class-table\n"
                                         "file (one line per channel: CHANNEL CITYSCAPES_CLASS; README, 'Class tables')")
                          ->capture_default_str());
  s.options.push_back(cmd.add_option("--input-size", s.input_size,
                                     "the network's input" + needs +
                                         ": WIDTHxHEIGHT, or one number for the photo's shorter side\n"
                                         "(the other in proportion, multiples of 8); default: the size the model was\n"
                                         "exported with, or 520 on the shorter side for a model that leaves it open"));
  s.options.push_back(cmd.add_option("--mean", s.mean,
                                     "per input channel, in the network's channel order, for values in 0..1" + needs)
                          ->delimiter(',')
                          ->capture_default_str());
  s.options.push_back(cmd.add_option("--std", s.std, "per input channel, as --mean (values 0..255 unscaled: 0.00392)" + needs)
                          ->delimiter(',')
                          ->capture_default_str());
  s.options.push_back(cmd.add_option("--channel-order", s.channel_order, "rgb (torchvision, SegFormer) or bgr (Caffe-style)" + needs)
                          ->capture_default_str()
                          ->check(CLI::IsMember({"rgb", "bgr"})));
}

SegmentDatasetSummary SegmentWithProgress(
    const Segmenter& segmenter,
    const std::function<SegmentDatasetSummary(const std::function<void(int done, int total)>& progress)>& segment) {
  const auto start = std::chrono::steady_clock::now();
  Progress progress("segmenting", "photo");
  SegmentDatasetSummary summary;
  {
    const InterruptScope interrupt;
    summary = segment([&](int done, int total) {
      const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      progress(done, total, done < total ? ", about " + DurationInWords(elapsed / done * (total - done)) + " left" : "");
      InterruptScope::ThrowIfRequested();
    });
  }
  std::printf("%s", FormatSegmentationSummary(summary, segmenter).c_str());
  return summary;
}

}  // namespace rigsim::cli
