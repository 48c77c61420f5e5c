#include "geometry/estimate_gauge.h"

#include <sstream>
#include <stdexcept>

#include "geometry/json_io.h"

namespace rigsim {

using json_io::Get;
using json_io::Json;

namespace {
constexpr char kLengthPrefix[] = "# rigsim length unit: ";
}  // namespace

std::string EstimateGauge::LengthUnit() const {
  return metric ? "lengths in metres (" + scale + ")" : "lengths not in metres: " + scale;
}

std::string EstimateGauge::Describe() const {
  return "rigsim calibration estimate: the rig frame is " + rig_frame + "'s, the world " + world + "; " + LengthUnit();
}

std::optional<EstimateGauge> EstimateGaugeFromJsonText(const std::string& text, const std::string& source) {
  const Json root = json_io::Parse(text, source);
  if (!root.is_object() || !root.contains("estimate")) return std::nullopt;
  const Json& e = root["estimate"];
  if (!e.is_object()) throw std::runtime_error(source + ": 'estimate' must be an object");
  EstimateGauge g;
  g.rig_frame = Get<std::string>(e, "rig_frame", source, "estimate");
  g.world = Get<std::string>(e, "world", source, "estimate");
  g.scale = Get<std::string>(e, "scale", source, "estimate");
  g.metric = Get<bool>(e, "metric", source, "estimate");
  if (e.contains("frames")) g.frames = Get<std::string>(e, "frames", source, "estimate");
  return g;
}

std::string EstimateRigToJsonText(const Rig& rig, const EstimateGauge& gauge) {
  Json root = Json::parse(RigToJsonText(rig));
  root["estimate"] = {{"rig_frame", gauge.rig_frame},
                      {"world", gauge.world},
                      {"scale", gauge.scale},
                      {"metric", gauge.metric},
                      {"frames", gauge.frames}};
  return root.dump(2) + "\n";
}

void WriteEstimateRig(const Rig& rig, const EstimateGauge& gauge, const std::filesystem::path& path) {
  json_io::WriteTextAtomic(path, EstimateRigToJsonText(rig, gauge));
}

std::string EstimateGaugeComment(const EstimateGauge& gauge) {
  return "# rigsim calibration estimate: the rig frame is " + gauge.rig_frame + "'s, the world " + gauge.world + "\n" +
         kLengthPrefix + (gauge.metric ? "metres (" + gauge.scale + ")" : "not metres: " + gauge.scale) + "\n";
}

std::optional<bool> MetricMarkInComments(const std::string& text) {
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind(kLengthPrefix, 0) == 0) return line.compare(sizeof(kLengthPrefix) - 1, 6, "metres") == 0;
  }
  return std::nullopt;
}

}  // namespace rigsim
