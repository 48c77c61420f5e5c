#include "dataset/render_shards.h"

#include <algorithm>
#include <map>
#include <stdexcept>

#include "dataset/coco.h"
#include "dataset/dataset.h"
#include "geometry/json_io.h"
#include "geometry/rig.h"

namespace rigsim {

namespace fs = std::filesystem;
using Json = nlohmann::json;

namespace {

// What a shard folder holds beyond its frames' images, merged rather than copied.
bool IsMergedFile(const fs::path& relative) {
  static const std::vector<std::string> merged = {"shard.json", "frames.json", "overlap.json", "poses.json",
                                                  "instances_coco.json"};
  return relative.has_parent_path() == false &&
         (std::find(merged.begin(), merged.end(), relative.string()) != merged.end() || relative.string()[0] == '.');
}

Json ReadJsonFile(const fs::path& path) {
  try {
    return Json::parse(json_io::ReadText(path));
  } catch (const Json::exception& e) {
    throw std::runtime_error(path.string() + ": not valid JSON (" + e.what() + ")");
  }
}

// The shards in shard order; refuses folders of other renders, repeats and gaps.
std::vector<std::pair<fs::path, RenderShardInfo>> CheckShards(const std::vector<fs::path>& dirs) {
  if (dirs.empty()) throw std::runtime_error("render-merge: no shard folders given");
  std::map<int, std::pair<fs::path, RenderShardInfo>> by_index;
  const RenderShardInfo first = ReadRenderShard(dirs[0]);
  for (const fs::path& dir : dirs) {
    RenderShardInfo info = ReadRenderShard(dir);
    if (info.render != first.render || info.count != first.count || info.frames_total != first.frames_total) {
      throw std::runtime_error(dir.string() + ": a shard of another render than " + dirs[0].string() +
                               " (its rig, frames or options differ); merge the shards of one render");
    }
    const auto [it, fresh] = by_index.emplace(info.index, std::make_pair(dir, info));
    if (!fresh) {
      throw std::runtime_error(dir.string() + ": shard " + std::to_string(info.index) + " is also " +
                               it->second.first.string() + "; give each shard once");
    }
  }
  std::string missing;
  for (int i = 0; i < first.count; ++i) {
    if (by_index.count(i) == 0) missing += (missing.empty() ? "" : ", ") + std::to_string(i);
  }
  if (!missing.empty()) {
    throw std::runtime_error("render-merge: shards " + missing + " of " + std::to_string(first.count) +
                             " are missing; render them (rigsim render ... --shard I/" + std::to_string(first.count) +
                             ") and merge all " + std::to_string(first.count) + " folders");
  }
  std::vector<std::pair<fs::path, RenderShardInfo>> shards;
  for (auto& [index, shard] : by_index) shards.push_back(std::move(shard));
  return shards;
}

// Copies every file of the shards' frames into `staging`; a file in two shards is an error.
void CopyShardFiles(const std::vector<std::pair<fs::path, RenderShardInfo>>& shards, const fs::path& staging) {
  for (size_t s = 0; s < shards.size(); ++s) {
    const fs::path& dir = shards[s].first;
    for (const fs::directory_entry& e : fs::recursive_directory_iterator(dir)) {
      if (!e.is_regular_file()) continue;
      const fs::path relative = fs::relative(e.path(), dir);
      if (IsMergedFile(relative)) continue;
      // rig.json and photometric.json are the same in every shard of one render (its hash).
      if (s > 0 && !relative.has_parent_path()) continue;
      const fs::path target = staging / relative;
      fs::create_directories(target.parent_path());
      if (!fs::copy_file(e.path(), target, fs::copy_options::skip_existing)) {
        throw std::runtime_error(e.path().string() + ": also written by another shard; merge the shards of one render");
      }
    }
  }
}

std::string MergedFrames(const std::vector<std::pair<fs::path, RenderShardInfo>>& shards) {
  Json merged;
  for (const auto& [dir, info] : shards) {
    Json frames = ReadJsonFile(DatasetLayout(dir).FramesJson());
    if (merged.is_null()) {
      merged = std::move(frames);
    } else {
      for (Json& f : frames.at("frames")) merged["frames"].push_back(std::move(f));
    }
  }
  return merged.dump(2) + "\n";  // as FramesToJsonText writes it
}

std::vector<FrameOverlapCounts> MergedOverlapCounts(const std::vector<std::pair<fs::path, RenderShardInfo>>& shards) {
  std::vector<FrameOverlapCounts> all;
  for (const auto& [dir, info] : shards) all.insert(all.end(), info.overlap.begin(), info.overlap.end());
  return all;
}

// poses.json: each camera's frames in frame order.
std::string MergedPoses(const std::vector<std::pair<fs::path, RenderShardInfo>>& shards) {
  Json merged;
  for (const auto& [dir, info] : shards) {
    Json poses = ReadJsonFile(DatasetLayout(dir).PosesJson());
    if (merged.is_null()) {
      merged = std::move(poses);
      continue;
    }
    for (size_t c = 0; c < merged.at("cameras").size(); ++c) {
      for (Json& f : poses.at("cameras").at(c).at("frames")) merged["cameras"][c]["frames"].push_back(std::move(f));
    }
  }
  return merged.dump() + "\n";
}

std::string MergedCoco(const std::vector<std::pair<fs::path, RenderShardInfo>>& shards) {
  CocoInstances coco;
  for (const auto& [dir, info] : shards) coco.AddAll(ReadJsonFile(DatasetLayout(dir).CocoJson()));
  return coco.ToJson().dump() + "\n";
}

}  // namespace

FrameRange ShardFrames(int num_frames, int index, int count) {
  if (count < 1 || index < 0 || index >= count) {
    throw std::invalid_argument("shard " + std::to_string(index) + " of " + std::to_string(count) + " does not exist");
  }
  const auto edge = [&](int i) { return int(int64_t(num_frames) * i / count); };
  return {edge(index), edge(index + 1)};
}

Json OverlapJson(const std::vector<std::string>& cameras, const std::vector<FrameOverlapCounts>& frames) {
  const size_t n = cameras.size();
  // Per frame the fraction of a's surface seen by b, summed in frame order, then averaged.
  std::vector<double> sum(n * n, 0.0);
  for (const FrameOverlapCounts& f : frames) {
    for (size_t a = 0; a < n; ++a) {
      for (size_t b = 0; b < n; ++b) {
        if (b != a && f.surface[a] > 0) sum[a * n + b] += double(f.visible[a * n + b]) / double(f.surface[a]);
      }
    }
  }
  const double num_frames = double(frames.size());
  Json pairs = Json::array();
  for (size_t a = 0; a < n; ++a) {
    for (size_t b = a + 1; b < n; ++b) {
      pairs.push_back({{"a", cameras[a]},
                       {"b", cameras[b]},
                       {"overlap_a_in_b", sum[a * n + b] / num_frames},
                       {"overlap_b_in_a", sum[b * n + a] / num_frames}});
    }
  }
  return {{"frames", frames.size()}, {"pairs", pairs}};
}

fs::path RenderShardJsonPath(const fs::path& dir) { return dir / "shard.json"; }

Json RenderShardJson(const RenderShardInfo& info) {
  Json overlap = Json::array();
  for (const FrameOverlapCounts& f : info.overlap) overlap.push_back({{"surface", f.surface}, {"visible", f.visible}});
  return {{"shard", info.index},         {"shards", info.count},           {"render", info.render},
          {"frames_total", info.frames_total}, {"first_frame", info.first_frame}, {"overlap", overlap}};
}

RenderShardInfo ReadRenderShard(const fs::path& dir) {
  const fs::path path = RenderShardJsonPath(dir);
  if (!fs::exists(path)) {
    throw std::runtime_error(dir.string() + ": no shard.json: not a shard of a render (rigsim render ... --shard I/N writes one)");
  }
  const Json j = ReadJsonFile(path);
  try {
    RenderShardInfo info;
    info.index = j.at("shard").get<int>();
    info.count = j.at("shards").get<int>();
    info.render = j.at("render").get<std::string>();
    info.frames_total = j.at("frames_total").get<int>();
    info.first_frame = j.at("first_frame").get<int>();
    for (const Json& f : j.at("overlap")) {
      info.overlap.push_back({f.at("surface").get<std::vector<size_t>>(), f.at("visible").get<std::vector<size_t>>()});
    }
    const FrameRange range = ShardFrames(info.frames_total, info.index, info.count);
    if (info.first_frame != range.begin || int(info.overlap.size()) != range.end - range.begin) {
      throw std::invalid_argument("its frames are not those of shard " + std::to_string(info.index));
    }
    return info;
  } catch (const std::exception& e) {
    throw std::runtime_error(path.string() + ": not a shard description rigsim wrote (" + e.what() + ")");
  }
}

void MergeRenderShards(const fs::path& out_dir, const std::vector<fs::path>& shard_dirs, bool force) {
  const auto shards = CheckShards(shard_dirs);
  StagedOutput staged(out_dir, force);
  const DatasetLayout layout(staged.staging_dir());
  CopyShardFiles(shards, staged.staging_dir());
  json_io::WriteTextAtomic(layout.FramesJson(), MergedFrames(shards));
  std::vector<std::string> cameras;
  for (const RigCamera& c : ReadRig(layout.RigJson()).cameras) cameras.push_back(c.name);
  json_io::WriteTextAtomic(layout.OverlapJson(), OverlapJson(cameras, MergedOverlapCounts(shards)).dump(2) + "\n");
  const DatasetLayout first(shards[0].first);
  if (fs::exists(first.PosesJson())) json_io::WriteTextAtomic(layout.PosesJson(), MergedPoses(shards));
  if (fs::exists(first.CocoJson())) json_io::WriteTextAtomic(layout.CocoJson(), MergedCoco(shards));
  staged.Commit();
}

}  // namespace rigsim
