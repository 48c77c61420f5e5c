#include "segmentation/segment_dataset.h"

#include <algorithm>
#include <chrono>
#include <fstream>

#include <nlohmann/json.hpp>

#include "dataset/dataset.h"
#include "dataset/image_io.h"
#include "dataset/label_image.h"
#include "geometry/rig.h"
#include "labels/cityscapes.h"

namespace rigsim {
namespace {

std::vector<std::string> CameraNames(const std::filesystem::path& dataset) {
  const DatasetLayout layout(dataset);
  std::vector<std::string> names;
  if (std::filesystem::exists(layout.RigJson())) {
    for (const RigCamera& c : ReadRig(layout.RigJson()).cameras) names.push_back(c.name);
    return names;
  }
  const std::filesystem::path images = dataset / "images";
  std::error_code ec;
  if (!std::filesystem::is_directory(images, ec)) {
    throw std::runtime_error(images.string() + ": no such folder: the photos go in images/<camera>/ (README, "
                             "'Calibrating your own photos')");
  }
  for (const auto& entry : std::filesystem::directory_iterator(images)) {
    const std::string name = entry.path().filename().string();
    if (entry.is_directory() && !name.empty() && name[0] != '.') names.push_back(name);
  }
  std::sort(names.begin(), names.end());
  if (names.empty()) throw std::runtime_error(images.string() + ": no camera folders: the photos go in images/<camera>/");
  return names;
}

void Compare(const ImageU8& truth, const ImageU8& network, SegmentDatasetSummary& summary) {
  const ReliableClasses reliable;
  ++summary.photos_with_truth;
  for (size_t i = 0; i < truth.data.size(); ++i) {
    const uint8_t t = truth.data[i], n = network.data[i];
    ++summary.per_class[t].truth;
    ++summary.per_class[n].network;
    const bool rt = reliable.IsReliable(t), rn = reliable.IsReliable(n);
    summary.reliable.truth += rt;
    summary.reliable.network += rn;
    summary.reliable.both += rt && rn;
    if (t == n) {
      ++summary.per_class[t].both;
      ++summary.pixels_agreeing;
    }
  }
  summary.pixels_compared += int64_t(truth.data.size());
}

nlohmann::json SummaryJson(const Segmenter& segmenter, const std::vector<SegmentedPhoto>& photos,
                           const std::vector<double>& seconds, const SegmentDatasetSummary& summary) {
  const SegmenterOptions& o = segmenter.options();
  nlohmann::json j;
  j["model"] = std::filesystem::absolute(o.model).lexically_normal().string();
  j["classes"] = segmenter.classes().name;
  j["class_table"] = nlohmann::json::array();
  for (int c = 0; c < segmenter.classes().size(); ++c) {
    const LabelClass* lc = FindClassById(segmenter.classes().label_ids[c]);
    j["class_table"].push_back({{"channel", c}, {"network_class", segmenter.classes().channel_names[c]},
                                {"cityscapes", lc ? std::string(lc->name) : ""}});
  }
  j["channel_order"] = o.channel_order == ChannelOrder::kRgb ? "rgb" : "bgr";
  j["mean"] = o.mean;
  j["std"] = o.std;
  j["photos"] = nlohmann::json::array();
  for (size_t i = 0; i < photos.size(); ++i) {
    j["photos"].push_back({{"camera", photos[i].camera}, {"frame", photos[i].frame}, {"seconds", seconds[i]}});
  }
  j["input_size"] = summary.first_input_size;
  j["seconds"] = summary.seconds;
  j["inference_seconds"] = summary.inference_seconds;
  int64_t total = 0;
  for (const auto& [id, n] : summary.pixels_per_class) total += n;
  nlohmann::json shares = nlohmann::json::object();
  for (const auto& [id, n] : summary.pixels_per_class) {
    const LabelClass* lc = FindClassById(id);
    shares[lc ? std::string(lc->name) : std::to_string(id)] = total > 0 ? double(n) / total : 0.0;
  }
  j["pixel_share_per_class"] = shares;
  if (summary.photos_with_truth > 0) {
    nlohmann::json truth;
    truth["photos"] = summary.photos_with_truth;
    truth["pixel_accuracy"] = double(summary.pixels_agreeing) / double(summary.pixels_compared);
    truth["reliable_mask_iou"] = summary.reliable.IoU();
    truth["per_class"] = nlohmann::json::object();
    for (const auto& [id, a] : summary.per_class) {
      const LabelClass* lc = FindClassById(id);
      truth["per_class"][lc ? std::string(lc->name) : std::to_string(id)] = {
          {"iou", a.IoU()}, {"truth_pixels", a.truth}, {"network_pixels", a.network}};
    }
    j["against_truth"] = truth;
  }
  return j;
}

}  // namespace

std::vector<SegmentedPhoto> PhotosToSegment(const std::filesystem::path& dataset) {
  const DatasetLayout layout(dataset);
  std::vector<SegmentedPhoto> photos;
  const std::vector<std::string> cameras = CameraNames(dataset);
  const FramesFile frames = layout.ReadFramesOrScan(cameras.front());
  for (const std::string& cam : cameras) {
    for (const Frame& f : frames.frames) {
      const std::filesystem::path truth = layout.Label(cam, f.name);
      photos.push_back({cam, f.name, layout.RequireImage(cam, f.name), std::filesystem::exists(truth) ? truth : ""});
    }
  }
  if (photos.empty()) {
    throw std::runtime_error((dataset / "images" / cameras.front()).string() + ": no photos (.png, .jpg, .tif, .exr)");
  }
  return photos;
}

SegmentDatasetSummary SegmentPhotos(const std::vector<SegmentedPhoto>& photos, const Segmenter& segmenter,
                                    const std::filesystem::path& out_dir,
                                    const std::function<void(int done, int total)>& progress) {
  const auto start = std::chrono::steady_clock::now();
  const double inference_before = segmenter.inference_seconds();
  SegmentDatasetSummary summary;
  std::vector<double> seconds;
  const DatasetLayout out(out_dir);
  for (const SegmentedPhoto& p : photos) {
    const auto photo_start = std::chrono::steady_clock::now();
    const ImageU8 rgb = ReadImageU8(p.photo, 3);
    if (summary.photos == 0) summary.first_input_size = segmenter.InputSize(rgb.width, rgb.height);
    const ImageU8 labels = segmenter.Segment(rgb);
    for (uint8_t id : labels.data) ++summary.pixels_per_class[id];
    if (!p.truth.empty()) Compare(ReadLabelImage(p.truth, labels.width, labels.height), labels, summary);
    for (const std::filesystem::path& file : {out.Label(p.camera, p.frame), out.LabelColor(p.camera, p.frame)}) {
      std::filesystem::create_directories(file.parent_path());
    }
    WriteImage(out.Label(p.camera, p.frame), labels);
    WriteImage(out.LabelColor(p.camera, p.frame), ColorizeLabels(labels));
    seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - photo_start).count());
    ++summary.photos;
    if (progress) progress(summary.photos, int(photos.size()));
  }
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  summary.inference_seconds = segmenter.inference_seconds() - inference_before;
  std::ofstream json(out_dir / "segmentation.json");
  json << SummaryJson(segmenter, photos, seconds, summary).dump(2) << "\n";
  if (!json) throw std::runtime_error((out_dir / "segmentation.json").string() + ": cannot write");
  return summary;
}

}  // namespace rigsim
