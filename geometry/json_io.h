// Small JSON helpers shared by the readers and writers of rigsim's files: typed access with
// errors that name the file and the JSON path, poses in one representation, and atomic writes.
#pragma once

#include <cstdint>
#include <filesystem>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>

#include <nlohmann/json.hpp>

#include "geometry/rigid3.h"

namespace rigsim::json_io {

using Json = nlohmann::json;

// Parses JSON text; throws std::runtime_error("<source>: invalid JSON: ...").
Json Parse(const std::string& text, const std::string& source);
Json ReadFile(const std::filesystem::path& path);
std::string ReadText(const std::filesystem::path& path);

// Returns j[key] converted to T or throws "<source>: <where>.<key>: ..." when missing or of the
// wrong type.
template <typename T>
T Get(const Json& j, const char* key, const std::string& source, const std::string& where) {
  if (!j.is_object() || !j.contains(key)) {
    throw std::runtime_error(source + ": " + where + ": missing field '" + key + "'");
  }
  const Json& v = j.at(key);
  if constexpr (std::is_integral_v<T> && !std::is_same_v<T, bool>) {
    // nlohmann converts a float (or an integer literal too long for 64 bits, which it parses as
    // a float) to an integer with a plain cast: undefined behaviour out of range. Accept only
    // integers that fit.
    const auto bad = [&](const char* why) {
      return std::runtime_error(source + ": " + where + "." + key + ": " + why + " (" + v.dump() + ")");
    };
    if (!v.is_number_integer()) throw bad("must be an integer");
    if (v.is_number_unsigned()) {
      if (v.get<uint64_t>() > static_cast<uint64_t>(std::numeric_limits<T>::max())) throw bad("out of range");
    } else {
      const int64_t x = v.get<int64_t>();
      if ((std::is_unsigned_v<T> && x < 0) ||
          (!std::is_unsigned_v<T> && (x < static_cast<int64_t>(std::numeric_limits<T>::min()) ||
                                      x > static_cast<int64_t>(std::numeric_limits<T>::max())))) {
        throw bad("out of range");
      }
    }
  }
  try {
    return v.get<T>();
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(source + ": " + where + "." + key + ": wrong type (" + e.what() + ")");
  }
}

// {"rotation_wxyz": [w,x,y,z], "translation": [x,y,z]}
Json PoseToJson(const Rigid3d& pose);
// The number, or null when it is unknown (nullopt) or not finite: JSON has no infinity or NaN.
Json OptionalNumber(const std::optional<double>& value);
// Reads that pose; `rotation_key` names the quaternion [w, x, y, z] where a file calls it otherwise.
Rigid3d PoseFromJson(const Json& j, const std::string& source, const std::string& where,
                     const std::string& rotation_key = "rotation_wxyz");

// Writes text to `path` through a temporary file in the same folder and a rename, so a reader
// never sees half a file.
void WriteTextAtomic(const std::filesystem::path& path, const std::string& text);

}  // namespace rigsim::json_io
