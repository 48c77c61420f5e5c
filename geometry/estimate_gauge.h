// The frame and unit of length a calibration's estimate is in. Images fix a rig only up to a
// similarity: the estimate's rig frame is one camera's, its world the rig frame at the first frame,
// and its lengths are metres only when a known distance made them so. A rig.json written by
// `rigsim calibrate` says so in an "estimate" record beside its cameras:
//
//   "estimate": { "rig_frame": "cam0", "world": "the rig frame at the first frame",
//                 "scale": "unit scale: |centre of cam1| = 1", "metric": false,
//                 "frames": "frames.json" }   // the estimate's rig pose per frame, beside rig.json
//
// A rig.json without it is a rig as built (the truth of a rendered dataset, a surveyed rig): its
// own rig frame, in metres. The exports of an estimate repeat the record as comments (Kalibr,
// OpenCV, COLMAP) or a key (nerfstudio) so that a file read on its own says what it holds.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "geometry/rig.h"

namespace rigsim {

struct EstimateGauge {
  std::string rig_frame;  // the camera whose frame is the rig frame
  std::string world = "the rig frame at the first frame";
  std::string scale;      // how the unit of length is fixed, in words
  bool metric = false;    // lengths in metres (a known distance fixed them)
  std::string frames;     // the estimate's rig trajectory: a frames.json beside the rig.json; "" when none

  // "lengths in metres (<scale>)" or "lengths not in metres: <scale>".
  std::string LengthUnit() const;
  // One line for a file's header: where the estimate's frames are and what its lengths mean.
  std::string Describe() const;
};

// The "estimate" record of a rig.json's text; nullopt when it has none. Throws std::runtime_error
// naming `source` when the record is malformed.
std::optional<EstimateGauge> EstimateGaugeFromJsonText(const std::string& text, const std::string& source);

// rig.json text of an estimate: the rig as RigToJsonText writes it, with the "estimate" record.
std::string EstimateRigToJsonText(const Rig& rig, const EstimateGauge& gauge);
// Writes atomically (temporary file, then rename).
void WriteEstimateRig(const Rig& rig, const EstimateGauge& gauge, const std::filesystem::path& path);

// The comment lines ("# ...\n") that mark an export of an estimate, and whether the comments of a
// file's text mark its lengths as metric (nullopt: the file carries no mark).
std::string EstimateGaugeComment(const EstimateGauge& gauge);
std::optional<bool> MetricMarkInComments(const std::string& text);

}  // namespace rigsim
