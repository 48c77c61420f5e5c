#include "pipeline/feature_cache.h"

#include "dataset/image_io.h"

namespace rigsim {

FeatureCache::FeatureCache(const DatasetLayout& layout, const Rig& rig, const FramesFile& frames,
                           const std::vector<std::filesystem::path>& image_paths, const std::vector<SemanticMode>& modes,
                           const FeatureOptions& features, const LabelIdSet& reliable, const LabelSource& labels,
                           int num_threads, const RigMasks* masks, const std::function<void(int done)>& photos_done)
    : num_cameras_(static_cast<int>(rig.cameras.size())), num_frames_(static_cast<int>(frames.frames.size())) {
  bool need_kind[2] = {false, false};
  bool need_labels = false;
  for (SemanticMode m : modes) {
    need_kind[Kind(m)] = true;
    need_labels = need_labels || NeedsLabels(m);
  }
  std::vector<int> kinds;
  std::vector<const LabelIdSet*> detect_only_on;
  for (int k = 0; k < 2; ++k) {
    if (!need_kind[k]) continue;
    kinds.push_back(k);
    detect_only_on.push_back(k == 1 ? &reliable : nullptr);
  }
  const int num_frames = num_frames_;
  std::vector<const ImageU8*> rig_mask(rig.cameras.size(), nullptr);
  for (size_t c = 0; masks != nullptr && c < rig.cameras.size(); ++c) {
    if (const CameraMask* m = masks->Of(rig.cameras[c].name)) rig_mask[c] = &m->keep;
  }
  const auto load = [&](int image) {
    const int cam = image / num_frames, frame = image % num_frames;
    const RigCamera& rc = rig.cameras[cam];
    LabelledImage out;
    out.rgb = ReadImageU8(image_paths[image], 3);
    out.rig_mask = rig_mask[cam];
    // Checks size and Cityscapes ids or colours; names the file.
    if (need_labels) {
      out.labels = LoadLabels(labels, layout, rc.name, frames.frames[frame].name, rc.camera.width(), rc.camera.height());
    }
    return out;
  };
  std::vector<std::vector<double>> time_s;
  std::vector<std::vector<FeatureSet>> detected = DetectFeaturesInImages(
      static_cast<int>(image_paths.size()), load, features, detect_only_on, num_threads, &time_s, photos_done);
  for (size_t i = 0; i < kinds.size(); ++i) {
    features_[kinds[i]] = std::move(detected[i]);
    time_s_[kinds[i]] = std::move(time_s[i]);
  }
}

double FeatureCache::DetectTimeS(SemanticMode m) const {
  double sum = 0.0;
  for (double t : time_s_[Kind(m)]) sum += t;
  return sum;
}

std::vector<int> FeatureCache::RemovedByMask(SemanticMode m) const {
  std::vector<int> removed(num_cameras_, 0);
  const std::vector<FeatureSet>& f = features_[Kind(m)];
  for (size_t v = 0; v < f.size() && num_frames_ > 0; ++v) removed[v / num_frames_] += f[v].removed_by_mask;
  return removed;
}

}  // namespace rigsim
