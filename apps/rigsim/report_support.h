// What the report and demo commands share: writing the teaching report of a calibration run
// (report/report_writer.h) into its own folder, atomically, and saying where it is.
#pragma once

#include <filesystem>
#include <string>

#include "dataset/output_folder.h"
#include "pipeline/calibration_run.h"
#include "report/report_writer.h"

namespace rigsim::cli {

// The scene a dataset was rendered from, for the report's 3D view: frames.json's "scene" as a
// path (absolute, or relative to the dataset or to the working folder), else the shipped scene of
// that name (assets/scenes/ of rigsim's data, common/data_dir.h); empty when none is found. Throws
// when rigsim's data folder is not found (the report needs its page from there anyway).
std::filesystem::path FindSceneOf(const std::filesystem::path& dataset, const FramesFile& frames);

// Writes the report into `out.dir` (StagedOutput: an existing folder is replaced only with
// out.force, and only when rigsim wrote it), prints its warnings to stderr and returns the path of
// its index.html.
std::filesystem::path WriteReportFolder(const CalibrationRun& run, const ReportOptions& options,
                                        const OutputFolderRequest& out);

}  // namespace rigsim::cli
