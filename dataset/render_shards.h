// A dataset rendered in shards (render --shard I/N) and merged (render-merge), so that a long
// trajectory renders on many machines and comes out byte-identical to a one-machine render.
//
// Shard I of N renders a contiguous block of the frames (ShardFrames) into its own folder: a
// dataset of its frames (frames.json, overlap.json, poses.json and instances_coco.json over those
// frames) plus shard.json:
//   {"shard": I, "shards": N, "render": "<StableHash of rig.json, the whole frames.json and the
//    render options>", "frames_total": F, "first_frame": K,
//    "overlap": [{"surface": [per camera], "visible": [[a][b] pixels of a seen by b]}, per frame]}
// The merge checks that the shards are those of one render, each once, and writes what the
// one-machine render writes: the overlap from the pixel counts (summed in frame order, as the
// render sums), poses and COCO entries in frame order.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace rigsim {

// Frames [begin, end) of shard `index` of `count`: contiguous, in order, sizes differing by at
// most one; every frame is in exactly one shard.
struct FrameRange {
  int begin = 0, end = 0;
};
FrameRange ShardFrames(int num_frames, int index, int count);

// Surface pixels of each camera and those of camera a visible in camera b, over one frame.
struct FrameOverlapCounts {
  std::vector<size_t> surface;  // per camera
  std::vector<size_t> visible;  // [a * num_cameras + b]
};

// overlap.json (renderer/render_dataset.h) from the counts of every frame, in frame order.
nlohmann::json OverlapJson(const std::vector<std::string>& cameras, const std::vector<FrameOverlapCounts>& frames);

struct RenderShardInfo {
  int index = 0, count = 1;
  std::string render;  // what the shards of one render share
  int frames_total = 0;
  int first_frame = 0;
  std::vector<FrameOverlapCounts> overlap;  // the shard's frames
};

nlohmann::json RenderShardJson(const RenderShardInfo& info);
// Reads DIR/shard.json; throws std::runtime_error naming the file when it is missing or malformed
// (the folder is then no shard of a render).
RenderShardInfo ReadRenderShard(const std::filesystem::path& dir);
std::filesystem::path RenderShardJsonPath(const std::filesystem::path& dir);

// Combines the shard folders into out_dir (StagedOutput: complete or nothing; `force` replaces a
// previous dataset). Throws std::runtime_error naming the folder when a folder is no shard, is a
// shard of another render, repeats a shard, or when shards are missing (naming them).
void MergeRenderShards(const std::filesystem::path& out_dir, const std::vector<std::filesystem::path>& shard_dirs,
                       bool force);

}  // namespace rigsim
