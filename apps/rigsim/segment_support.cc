#include "apps/rigsim/segment_support.h"

#include <chrono>
#include <cstdio>
#include <stdexcept>

#include <unistd.h>

#include "apps/rigsim/interrupt.h"
#include "apps/rigsim/progress.h"
#include "common/format.h"
#include "labels/cityscapes.h"

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

SegmentDatasetSummary SegmentWithProgress(const std::vector<SegmentedPhoto>& photos, const Segmenter& segmenter,
                                          const std::filesystem::path& out_dir) {
  const bool tty = ::isatty(2);
  const auto start = std::chrono::steady_clock::now();
  int last_quarter = -1;
  SegmentDatasetSummary summary;
  {
    const InterruptScope interrupt;
    summary = SegmentPhotos(photos, segmenter, out_dir, [&](int done, int total) {
      const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      std::string line = "segmenting " + std::to_string(done) + "/" + Count(total, "photo");
      if (done < total) line += ", about " + DurationInWords(elapsed / done * (total - done)) + " left";
      if (tty) {
        std::fprintf(stderr, "\r\033[K%s%s", line.c_str(), done == total ? "\n" : "");
      } else if (done * 4 / total != last_quarter || done == total) {
        last_quarter = done * 4 / total;
        std::fprintf(stderr, "%s\n", line.c_str());
      }
      std::fflush(stderr);
      InterruptScope::ThrowIfRequested();
    });
  }
  const ClassTable& table = segmenter.classes();
  std::printf("segmented %s with %s (classes %s, input %dx%d) in %.1f s: %.2f s per photo, %.2f s of it in the "
              "network\n",
              Count(summary.photos, "photo").c_str(), segmenter.options().model.filename().string().c_str(), table.name.c_str(),
              summary.first_input_size[0], summary.first_input_size[1], summary.seconds, summary.seconds / summary.photos,
              summary.inference_seconds / summary.photos);
  int64_t total = 0;
  for (const auto& [id, n] : summary.pixels_per_class) total += n;
  std::string shares;
  for (const auto& [id, n] : summary.pixels_per_class) {
    if (n * 100 < total) continue;  // under 1%
    const LabelClass* c = FindClassById(id);
    char buf[64];
    std::snprintf(buf, sizeof buf, "%s%s %.0f%%", shares.empty() ? "" : ", ", c ? std::string(c->name).c_str() : "?",
                  100.0 * n / total);
    shares += buf;
  }
  std::printf("classes (share of pixels, 1%% or more): %s\n", shares.c_str());
  if (summary.photos_with_truth > 0) {
    std::printf("against the true labels of %s: %.1f%% of pixels agree; the reliable-class mask (what --semantics "
                "mask detects on) has IoU %.3f; per class (IoU, share of the truth):\n",
                Count(summary.photos_with_truth, "photo").c_str(), 100.0 * summary.pixels_agreeing / summary.pixels_compared, summary.reliable.IoU());
    for (const auto& [id, a] : summary.per_class) {
      if (a.truth == 0) continue;
      const LabelClass* c = FindClassById(id);
      std::printf("  %-14s IoU %.3f  %5.1f%%\n", c ? std::string(c->name).c_str() : "?", a.IoU(),
                  100.0 * a.truth / summary.pixels_compared);
    }
  }
  return summary;
}

}  // namespace rigsim::cli
