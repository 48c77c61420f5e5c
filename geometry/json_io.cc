#include "geometry/json_io.h"

#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <unistd.h>

namespace rigsim::json_io {

Json Parse(const std::string& text, const std::string& source) {
  try {
    return Json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    // parse_error, and out_of_range for numbers beyond double ("1e999"; found by fuzz_rig_json).
    throw std::runtime_error(source + ": invalid JSON: " + e.what());
  }
}

std::string ReadText(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path.string() + ": cannot open file");
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

Json ReadFile(const std::filesystem::path& path) { return Parse(ReadText(path), path.string()); }

Json PoseToJson(const Rigid3d& pose) {
  const Eigen::Quaterniond& q = pose.rotation;
  return Json{{"rotation_wxyz", {q.w(), q.x(), q.y(), q.z()}},
              {"translation", {pose.translation.x(), pose.translation.y(), pose.translation.z()}}};
}

Json OptionalNumber(const std::optional<double>& value) {
  return value && std::isfinite(*value) ? Json(*value) : Json(nullptr);
}

Rigid3d PoseFromJson(const Json& j, const std::string& source, const std::string& where, const std::string& rotation_key) {
  const auto q = Get<std::vector<double>>(j, rotation_key.c_str(), source, where);
  const auto t = Get<std::vector<double>>(j, "translation", source, where);
  if (q.size() != 4 || t.size() != 3) {
    throw std::runtime_error(source + ": " + where + ": " + rotation_key + " needs 4 numbers and translation 3");
  }
  for (double v : q) if (!std::isfinite(v)) throw std::runtime_error(source + ": " + where + ": non-finite rotation");
  for (double v : t) if (!std::isfinite(v)) throw std::runtime_error(source + ": " + where + ": non-finite translation");
  const Eigen::Quaterniond quat(q[0], q[1], q[2], q[3]);
  if (std::abs(quat.norm() - 1.0) > 1e-3) {
    throw std::runtime_error(source + ": " + where + ": " + rotation_key + " is not a unit quaternion (norm " +
                             std::to_string(quat.norm()) + ")");
  }
  return Rigid3d(quat, Eigen::Vector3d(t[0], t[1], t[2]));
}

void WriteTextAtomic(const std::filesystem::path& path, const std::string& text) {
  const std::filesystem::path tmp = path.string() + ".tmp" + std::to_string(::getpid());
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error(path.string() + ": cannot write file");
    out << text;
    out.flush();
    if (!out) {
      std::filesystem::remove(tmp);
      throw std::runtime_error(path.string() + ": write failed");
    }
  }
  std::filesystem::rename(tmp, path);
}

}  // namespace rigsim::json_io
