// A teaching report of one calibration: a folder that opens from disk (file://) in any current
// browser, offline, with no server. index.html walks a class through it:
//   1. the scene and the rig in 3D (three.js): the glTF scene, the true and estimated camera
//      frustums (the estimate aligned as `rigsim evaluate` aligns it), each field of view through
//      its lens, the trajectory, the triangulated points;
//   2. each camera's views: photo, labels (opacity, legend), instances, depth, keypoints coloured
//      by whether the semantic mask keeps them;
//   3. each camera pair: matches as inliers, outliers and wrong by the ground truth per mode, the
//      true overlap shaded, a clicked point's epipolar curve under the estimate and the truth
//      and its true correspondence;
//   4. the pipeline step by step; 5. the numbers (the CLI's tables, a sweep's plots and summary).
//
// Layout (everything the page loads is a <script src> or an <img src>, which file:// allows;
// a page opened from disk may not fetch() its own files):
//   index.html, report.css, report.js      the page (report/web/)
//   three/                                 three.js r111, GLTFLoader, OrbitControls, licence
//   data/report.js                         RIGSIM.put("report", {...}): everything but the bulk
//   data/scene.js                          RIGSIM.put("scene", "<GLB as base64>")
//   data/view_c<C>_f<F>.js                 keypoints per mode, mask flags, quantised ranges
//   data/pair_c<A>_c<B>.js                 matches per frame and mode with their flags, overlap
//   img/c<C>_f<F>_{rgb,depth}.jpg, _{labels,instances}.png   images scaled for the screen
//   sweep/                                 a sweep's report.md, summary.json and plots (--sweep)
// The data format is described in report/README.md.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "pipeline/calibration_run.h"

namespace rigsim {

struct ReportOptions {
  // Images are scaled down (never up) to this width for the screen.
  int max_image_width = 960;
  // Width of the range grid the page lifts a clicked pixel with (the true correspondence).
  int depth_grid_width = 480;
  // Width of the grid of the ground-truth overlap shading.
  int overlap_grid_width = 160;
  // At most this many triangulated points per mode in the 3D view (an even subsample).
  int max_points = 20000;
  // The glTF scene (.glb) shown in the 3D view; empty: the rig without the scene.
  std::filesystem::path scene;
  // A sweep's output folder (report.md, summary.json, plots/) for the numbers; empty: none.
  std::filesystem::path sweep_dir;
  // Where three.js r111 is (Debian's libjs-three) and the page's own files; an empty web_dir is
  // the shipped page, report/web/ of rigsim's data folder (common/data_dir.h).
  std::filesystem::path three_js_dir = RIGSIM_THREE_JS_DIR;
  std::filesystem::path web_dir;
  // Shown on the page: how the report was made.
  std::string command;
  std::string tool_version;

  // Throws std::invalid_argument naming the first bad field.
  void Check() const;
};

// The page's own files (index.html, its scripts and style sheet) from options.web_dir, or from
// rigsim's data folder when that is empty. Throws std::runtime_error naming the first one missing:
// the commands call it before they calibrate, WriteReport copies them.
std::vector<std::filesystem::path> ReportPageFiles(const ReportOptions& options);

// Writes the report of `run` into `dir`, an existing folder (the caller stages it: dataset.h
// StagedOutput). The run must have been calibrated with RigCalibrationOptions::keep_details.
// Returns warnings (a scene that could not be embedded, missing ground-truth images). Throws
// std::runtime_error naming the file on what cannot be read or written.
std::vector<std::string> WriteReport(const CalibrationRun& run, const ReportOptions& options,
                                     const std::filesystem::path& dir);

}  // namespace rigsim
