#include "apps/rigsim/report_support.h"

#include <cstdio>

#include "common/data_dir.h"
#include "dataset/dataset.h"

namespace rigsim::cli {
namespace fs = std::filesystem;

fs::path FindSceneOf(const fs::path& dataset, const FramesFile& frames) {
  if (frames.scene.empty()) return {};
  const fs::path scene = frames.scene;
  for (const fs::path& candidate : {scene, dataset / scene, DataDir() / "assets" / "scenes" / scene.filename()}) {
    if (fs::is_regular_file(candidate)) return candidate;
  }
  return {};
}

fs::path WriteReportFolder(const CalibrationRun& run, const ReportOptions& options, const OutputFolderRequest& out) {
  StagedOutput staged(out);
  for (const std::string& w : WriteReport(run, options, staged.staging_dir())) {
    std::fprintf(stderr, "warning: report: %s\n", w.c_str());
  }
  staged.Commit();
  return fs::absolute(out.dir / "index.html").lexically_normal();
}

}  // namespace rigsim::cli
