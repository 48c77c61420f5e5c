// COLMAP (Debian's colmap 3.8) run on a rigsim dataset as a peer to compare with: the same
// images, the true intrinsics given and held fixed, on the CPU:
//   feature_extractor   once per camera (its images listed, its model and parameters given:
//                       COLMAP takes one set of intrinsics per run), cx, cy + 0.5 (COLMAP's pixel
//                       centres are at .5)
//   exhaustive_matcher
//   mapper              --Mapper.ba_refine_focal_length/principal_point/extra_params 0
//   model_converter     each sub-model to text
// and the largest sub-model read as a rig (evaluation/rig_estimate.h). COLMAP's CPU matcher uses
// randomised kd-trees: two runs on the same images can differ.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "dataset/dataset.h"
#include "evaluation/rig_estimate.h"
#include "geometry/rig.h"

namespace rigsim {

struct ColmapPeerOptions {
  std::string program = "colmap";
  int num_threads = 2;
};

struct ColmapPeerResult {
  bool success = false;
  std::string failure_reason;  // the step that failed and the end of its log
  RigEstimate estimate;        // valid on success
  int images = 0;              // in the dataset
  int registered = 0;          // in the model read
  double time_s = 0.0;         // wall time of the COLMAP steps
  double extract_time_s = 0.0, match_time_s = 0.0, mapper_time_s = 0.0;
};

// True when COLMAP can be run (on the PATH).
bool ColmapAvailable(const ColmapPeerOptions& options = {});

// Runs COLMAP on the dataset's images in `work_dir` (created; database, logs and sparse/ go there).
// Never throws for COLMAP's own failures: they are reported in the result.
ColmapPeerResult RunColmapPeer(const std::filesystem::path& dataset_dir, const Rig& truth, const FramesFile& frames,
                               const std::filesystem::path& work_dir, const ColmapPeerOptions& options = {});

}  // namespace rigsim
