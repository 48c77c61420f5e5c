#include "pipeline/segmentation_run.h"

#include <algorithm>
#include <cstdio>

#include "common/format.h"
#include "labels/cityscapes.h"

namespace rigsim {

std::vector<CommandInput> SegmenterInputs(const SegmenterOptions& options, const std::string& model_option) {
  std::vector<CommandInput> inputs = {{options.model, model_option}};
  const std::vector<std::string> builtin = BuiltinClassTableNames();
  if (std::find(builtin.begin(), builtin.end(), options.classes) == builtin.end()) {
    inputs.push_back({options.classes, "--classes"});
  }
  return inputs;
}

std::string FormatSegmentationSummary(const SegmentDatasetSummary& summary, const Segmenter& segmenter) {
  std::string text;
  char line[1024];
  const ClassTable& table = segmenter.classes();
  std::snprintf(line, sizeof line,
                "segmented %s with %s (classes %s, input %dx%d) in %.1f s: %.2f s per photo, %.2f s of it in the "
                "network\n",
                Count(summary.photos, "photo").c_str(), segmenter.options().model.filename().string().c_str(),
                table.name.c_str(), summary.first_input_size[0], summary.first_input_size[1], summary.seconds,
                summary.seconds / summary.photos, summary.inference_seconds / summary.photos);
  text += line;
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
  text += "classes (share of pixels, 1% or more): " + shares + "\n";
  if (summary.photos_with_truth > 0) {
    std::snprintf(line, sizeof line,
                  "against the true labels of %s: %.1f%% of pixels agree; the reliable-class mask (what --semantics "
                  "mask detects on) has IoU %.3f; per class (IoU, share of the truth):\n",
                  Count(summary.photos_with_truth, "photo").c_str(), 100.0 * summary.pixels_agreeing / summary.pixels_compared,
                  summary.reliable.IoU());
    text += line;
    for (const auto& [id, a] : summary.per_class) {
      if (a.truth == 0) continue;
      const LabelClass* c = FindClassById(id);
      std::snprintf(line, sizeof line, "  %-14s IoU %.3f  %5.1f%%\n", c ? std::string(c->name).c_str() : "?", a.IoU(),
                    100.0 * a.truth / summary.pixels_compared);
      text += line;
    }
  }
  return text;
}

}  // namespace rigsim
