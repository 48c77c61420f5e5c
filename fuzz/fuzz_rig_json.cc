// Fuzzes the rig.json reader (geometry/rig.h RigFromJsonText), an estimate's record in it
// (geometry/estimate_gauge.h) and the check that each camera covers its image
// (geometry/camera_validation.h), then requires that a rig that was accepted survives writing and
// reading back unchanged, with its estimate record.
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>

#include "geometry/camera_validation.h"
#include "geometry/estimate_gauge.h"
#include "geometry/rig.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  rigsim::Rig rig;
  std::optional<rigsim::EstimateGauge> gauge;
  try {
    rig = rigsim::RigFromJsonText(text, "fuzz.json");
    gauge = rigsim::EstimateGaugeFromJsonText(text, "fuzz.json");
  } catch (const std::runtime_error&) {
    return 0;  // rejected with a message: fine
  }
  (void)rigsim::MetricMarkInComments(text);
  if (gauge) {
    const std::optional<rigsim::EstimateGauge> again =
        rigsim::EstimateGaugeFromJsonText(rigsim::EstimateRigToJsonText(rig, *gauge), "round trip");
    if (!again || again->scale != gauge->scale || again->metric != gauge->metric || again->frames != gauge->frames) {
      __builtin_trap();
    }
  }
  try {
    rigsim::CheckRigCoversImages(rig, "fuzz.json");
  } catch (const std::runtime_error&) {
    // an impossible lens for its image: fine
  }
  const rigsim::Rig back = rigsim::RigFromJsonText(rigsim::RigToJsonText(rig), "round trip");
  if (back.cameras.size() != rig.cameras.size()) __builtin_trap();
  for (size_t i = 0; i < rig.cameras.size(); ++i) {
    const rigsim::RigCamera &a = rig.cameras[i], &b = back.cameras[i];
    if (a.name != b.name || a.camera.model() != b.camera.model() || a.camera.params() != b.camera.params() ||
        a.camera.width() != b.camera.width() || a.camera.height() != b.camera.height() ||
        a.cam_from_rig.has_value() != b.cam_from_rig.has_value()) {
      __builtin_trap();
    }
  }
  return 0;
}
