#include "dataset/label_source.h"

#include <cstdio>
#include <stdexcept>

#include "dataset/label_image.h"

namespace rigsim {

std::string LabelSource::KindName() const {
  switch (kind) {
    case Kind::kTruth: return "truth";
    case Kind::kFolder: return "folder";
    case Kind::kNoisy: return "noisy";
  }
  return "?";
}

std::string LabelSource::Describe() const {
  switch (kind) {
    case Kind::kTruth: return "truth";
    case Kind::kFolder: return "folder " + folder.string();
    case Kind::kNoisy: {
      char buf[160];
      std::snprintf(buf, sizeof(buf), "noisy truth (boundary %d px, confusion %g, blobs %d px, seed %llu)",
                    noise.boundary_px, noise.confusion_rate, noise.blob_size_px,
                    static_cast<unsigned long long>(noise.seed));
      return buf;
    }
  }
  return "?";
}

void LabelSource::Check() const {
  if (kind == Kind::kNoisy) noise.Check();
  if (kind == Kind::kFolder && !std::filesystem::is_directory(folder)) {
    throw std::runtime_error(folder.string() + ": no such label folder (expected <folder>/<cam>/<frame>.png)");
  }
}

std::filesystem::path LabelSourcePath(const LabelSource& source, const DatasetLayout& layout, const std::string& camera,
                                      const std::string& frame) {
  if (source.kind == LabelSource::Kind::kFolder) return source.folder / camera / (frame + ".png");
  return layout.Label(camera, frame);
}

ImageU8 LoadLabels(const LabelSource& source, const DatasetLayout& layout, const std::string& camera,
                   const std::string& frame, int width, int height) {
  const std::filesystem::path path = LabelSourcePath(source, layout, camera, frame);
  if (!std::filesystem::exists(path)) {
    if (source.kind == LabelSource::Kind::kFolder && !std::filesystem::is_directory(source.folder / camera)) {
      throw std::runtime_error(NoCameraFolderMessage(source.folder, camera, "label images"));
    }
    throw std::runtime_error(path.string() + ": label image missing (the semantic mode needs labels; source: " +
                             source.KindName() + ")");
  }
  switch (source.kind) {
    case LabelSource::Kind::kTruth: return ReadLabelImage(path, width, height);
    case LabelSource::Kind::kFolder: return ReadLabelImageIdsOrColors(path, width, height);
    case LabelSource::Kind::kNoisy:
      return ApplySegmentationNoise(ReadLabelImage(path, width, height), source.noise, camera, frame);
  }
  throw std::logic_error("LoadLabels: unknown label source");
}

}  // namespace rigsim
