// Small JSON helpers shared by the readers and writers of rigsim's files: typed access with
// errors that name the file and the JSON path, poses in one representation, and atomic writes.
#pragma once

#include <filesystem>
#include <string>

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
  try {
    return j.at(key).get<T>();
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(source + ": " + where + "." + key + ": wrong type (" + e.what() + ")");
  }
}

// {"rotation_wxyz": [w,x,y,z], "translation": [x,y,z]}
Json PoseToJson(const Rigid3d& pose);
Rigid3d PoseFromJson(const Json& j, const std::string& source, const std::string& where);

// Writes text to `path` through a temporary file in the same folder and a rename, so a reader
// never sees half a file.
void WriteTextAtomic(const std::filesystem::path& path, const std::string& text);

}  // namespace rigsim::json_io
