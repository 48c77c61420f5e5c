// The camera views of a report: images scaled for the screen and each view's data file.
#include <cmath>
#include <filesystem>
#include <map>
#include <stdexcept>

#include "calibrator/features/semantics.h"
#include "dataset/image_io.h"
#include "dataset/label_source.h"
#include "report/report_images.h"
#include "report/report_parts.h"

namespace rigsim::report_parts {
namespace fs = std::filesystem;
using Json = nlohmann::json;

namespace {

// Built by appending: GCC 12 warns falsely (-Wrestrict) on "c" + std::to_string(c) + ....
std::string ViewStem(int c, int f) {
  std::string stem = "c";
  stem += std::to_string(c);
  stem += "_f";
  stem += std::to_string(f);
  return stem;
}

// The labels the run's mask modes saw (its label source), or the rendered truth when no mode
// used labels; empty when there are none.
ImageU8 RunLabels(const ReportContext& ctx, const std::string& cam, const std::string& frame, int w, int h) {
  const DatasetLayout layout = ctx.Layout();
  const LabelSource source = ctx.run.labels_used ? ctx.run.options.labels : LabelSource::Truth();
  if (source.kind == LabelSource::Kind::kTruth && !fs::exists(layout.Label(cam, frame))) return {};
  return LoadLabels(source, layout, cam, frame, w, h);
}

// Pixel of a keypoint (nearest, clamped), as features.cc reads its class and mask.
std::pair<int, int> NearestPixel(const Eigen::Vector2d& px, int w, int h) {
  return {std::clamp(int(std::lround(px.x())), 0, w - 1), std::clamp(int(std::lround(px.y())), 0, h - 1)};
}

}  // namespace

Json WriteViews(ReportContext& ctx) {
  const DatasetLayout layout = ctx.Layout();
  const Rig& rig = ctx.run.inputs.rig;
  fs::create_directories(ctx.dir / "img");
  fs::create_directories(ctx.dir / "data");
  Json views = Json::array();
  for (int c = 0; c < ctx.NumCameras(); ++c) {
    const RigCamera& rc = rig.cameras[c];
    const int w = rc.camera.width(), h = rc.camera.height();
    const double scale = DisplayScale(w, ctx.options.max_image_width);
    const int dw = std::max(1, int(std::lround(w * scale))), dh = std::max(1, int(std::lround(h * scale)));
    Json per_frame = Json::array();
    for (int f = 0; f < ctx.NumFrames(); ++f) {
      const std::string& frame = ctx.run.inputs.frames.frames[f].name;
      const std::string stem = ViewStem(c, f);
      Json view = {{"camera", c}, {"frame", f}, {"width", dw}, {"height", dh}, {"data", "data/view_" + stem + ".js"}};
      const ImageU8 rgb = ReadImageU8(layout.RequireImage(rc.name, frame), 3);
      WriteImage(ctx.dir / "img" / (stem + "_rgb.jpg"), ScaleRgb(rgb, scale));
      view["rgb"] = "img/" + stem + "_rgb.jpg";

      const ImageU8 labels = RunLabels(ctx, rc.name, frame, w, h);
      Json classes = Json::array();
      if (!labels.empty()) {
        WriteImage(ctx.dir / "img" / (stem + "_labels.png"), ColourLabels(SampleNearest(labels, dw, dh)));
        view["labels"] = "img/" + stem + "_labels.png";
        std::map<int, size_t> count;
        for (uint8_t id : labels.data) ++count[id];
        for (const auto& [id, n] : count) classes.push_back({id, double(n) / labels.data.size()});
      }
      view["classes"] = classes;  // [label id, share of the pixels]
      if (fs::exists(layout.Instance(rc.name, frame))) {
        const ImageU16 instances = ReadImageU16(layout.Instance(rc.name, frame));
        WriteImage(ctx.dir / "img" / (stem + "_instances.png"), ColourInstances(SampleNearest(instances, dw, dh)));
        view["instances"] = "img/" + stem + "_instances.png";
      }
      Json data;
      if (fs::exists(layout.Depth(rc.name, frame))) {
        const ImageF range = ReadImageF(layout.Depth(rc.name, frame));
        WriteImage(ctx.dir / "img" / (stem + "_depth.jpg"), ColourDepth(SampleNearest(range, dw, dh), 0.5, 200.0));
        view["depth"] = "img/" + stem + "_depth.jpg";
        const int gw = std::min(w, ctx.options.depth_grid_width);
        const int gh = std::max(1, int(std::lround(double(h) * gw / w)));
        data["depth"] = {{"width", gw}, {"height", gh}, {"q", Base64Of(QuantiseRanges(SampleNearest(range, gw, gh)))}};
      } else {
        data["depth"] = nullptr;
      }
      // Which pixels the mask modes may detect on (the eroded reliable-class mask of features.cc).
      ImageU8 mask;
      if (!labels.empty()) {
        mask = ReliableMask(labels, ctx.run.options.reliable.Ids(), ctx.run.options.features.mask_erosion_px);
      }
      Json keypoints = Json::object();
      for (size_t m = 0; m < ctx.run.modes.size(); ++m) {
        const RigCalibrationDetails* d = ctx.Details(m);
        if (!d || d->matches.keypoints.empty()) continue;
        const auto& kps = d->matches.keypoints.at(f).at(c);
        std::vector<float> xy;
        std::vector<uint8_t> in_mask, classes_of;
        for (size_t k = 0; k < kps.size(); ++k) {
          xy.push_back(float(kps[k].x()));
          xy.push_back(float(kps[k].y()));
          if (!mask.empty()) {
            const auto [x, y] = NearestPixel(kps[k], w, h);
            in_mask.push_back(mask.at(x, y) ? 1 : 0);
          }
          const auto& cls = d->matches.keypoint_classes;
          classes_of.push_back(cls.empty() ? kUnlabeledId : cls.at(f).at(c).at(k));
        }
        keypoints[ctx.run.results[m].semantic_mode] = {{"count", kps.size()},
                                                       {"xy", Base64Of(xy)},
                                                       {"in_mask", mask.empty() ? Json(nullptr) : Json(Base64Of(in_mask))},
                                                       {"classes", Base64Of(classes_of)}};
      }
      data["keypoints"] = keypoints;
      data["scale"] = scale;
      WriteDataScript(ctx.dir / "data" / ("view_" + stem + ".js"), "view/" + std::to_string(c) + "/" + std::to_string(f),
                      data);
      per_frame.push_back(view);
    }
    views.push_back(per_frame);
  }
  return views;
}

}  // namespace rigsim::report_parts
