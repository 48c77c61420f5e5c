#include "dataset/output_folder.h"
#include "dataset/output_file.h"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <set>
#include <stdexcept>

#include <cerrno>
#include <csignal>

#include <fcntl.h>
#include <stdio.h>
#include <unistd.h>

#include "geometry/json_io.h"

namespace rigsim {
namespace fs = std::filesystem;

namespace {

// `inner` is `outer` or lies inside it (both absolute and canonical).
bool IsWithin(const fs::path& inner, const fs::path& outer) {
  auto i = inner.begin();
  for (auto o = outer.begin(); o != outer.end(); ++o, ++i) {
    if (o->empty()) continue;  // the trailing "" of "/a/b/"
    if (i == inner.end() || *i != *o) return false;
  }
  return true;
}

// The absolute form of `p` with symbolic links and "..", "." resolved as far as it exists.
fs::path Resolved(const fs::path& p) {
  std::error_code ec;
  fs::path abs = fs::absolute(p, ec);
  if (ec) return p;
  fs::path canonical = fs::weakly_canonical(abs, ec);
  if (ec) return abs.lexically_normal();
  if (canonical.filename().empty() && canonical.has_parent_path() && canonical != canonical.root_path()) {
    canonical = canonical.parent_path();  // "/a/b/" -> "/a/b"
  }
  return canonical;
}

// The staging folders StagedOutput builds beside an output: ".<name>.partial-<pid>-...".
bool IsStagingName(const std::string& name) { return name.size() > 1 && name[0] == '.' && name.find(".partial-") != std::string::npos; }

struct Marker {
  std::string written_by;
  std::set<std::string> entries;
};

Marker ReadMarker(const fs::path& dir) {
  const fs::path path = dir / kOutputMarker;
  const json_io::Json doc = json_io::Parse(json_io::ReadText(path), path.string());
  Marker m;
  if (!doc.is_object() || !doc.contains("written_by") || !doc["written_by"].is_string() || !doc.contains("entries") ||
      !doc["entries"].is_array()) {
    throw std::runtime_error(path.string() + ": not a marker rigsim wrote (it writes written_by and entries)");
  }
  m.written_by = doc["written_by"].get<std::string>();
  for (const json_io::Json& e : doc["entries"]) {
    if (e.is_string()) m.entries.insert(e.get<std::string>());
  }
  return m;
}

std::string ListNames(const std::vector<std::string>& names) {
  std::string list;
  const size_t shown = std::min<size_t>(names.size(), 3);
  for (size_t i = 0; i < shown; ++i) list += (i > 0 ? ", " : "") + names[i];
  if (names.size() > shown) list += " and " + std::to_string(names.size() - shown) + " more";
  return list;
}

}  // namespace

OutputFolderState CheckOutputFolder(const OutputFolderRequest& request) {
  const std::string given = request.dir.string();
  const std::string name = request.option.empty() ? given : request.option + " " + given;
  const std::string another = request.option.empty() ? "another folder with --out" : "another " + request.option;
  auto fail = [&](const std::string& why) { throw std::runtime_error(name + ": " + why); };
  if (request.dir.empty()) fail("give a folder");
  // Why the special folders and foreign files are refused.
  const std::string replaces = "rigsim replaces the whole folder it writes into, so it writes only into a new folder, "
                               "an empty one or one it wrote itself, --force or not; choose " + another;
  const fs::path dir = Resolved(request.dir);
  std::error_code ec;
  const fs::file_status status = fs::status(dir, ec);
  const bool exists = fs::exists(status);
  if (exists && !fs::is_directory(status)) fail("is a file, not a folder; choose " + another + " (a new folder)");
  if (dir == dir.root_path()) fail("is the root folder; " + replaces);
  if (const char* home = std::getenv("HOME"); home != nullptr && *home != '\0') {
    const fs::path h = Resolved(home);
    if (IsWithin(h, dir)) fail(std::string(h == dir ? "is your home folder" : "holds your home folder (" + h.string() + ")") + "; " + replaces);
  }
  if (const fs::path cwd = fs::current_path(ec); !ec && IsWithin(Resolved(cwd), dir)) {
    fail(std::string(Resolved(cwd) == dir ? "is the working folder" : "holds the working folder (" + cwd.string() + ")") +
         "; " + replaces);
  }
  for (const CommandInput& input : request.inputs) {
    const fs::path in = Resolved(input.path);
    if (IsWithin(in, dir)) {
      fail((in == dir ? "is " : "holds ") + input.path.string() + ", an input of this command (" + input.what + "); choose " +
           another);
    }
    if (fs::is_directory(in, ec) && IsWithin(dir, in)) {
      fail("lies inside " + input.path.string() + ", an input of this command (" + input.what + "); choose " + another);
    }
  }
  if (!exists) return {OutputFolderState::kAbsent, ""};
  if (fs::is_empty(dir, ec) && !ec) return {OutputFolderState::kEmpty, ""};
  if (!fs::is_regular_file(dir / kOutputMarker, ec)) {
    fail("exists and holds files that rigsim did not write (it has no " + std::string(kOutputMarker) + "); " + replaces +
         " (or empty it yourself, if nothing in it is yours to keep)");
  }
  Marker marker;
  try {
    marker = ReadMarker(dir);
  } catch (const std::runtime_error& e) {
    fail(std::string("holds a ") + kOutputMarker + " that rigsim cannot read (" + e.what() + "); " + replaces);
  }
  std::vector<std::string> foreign;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string entry = it->path().filename().string();
    if (entry == kOutputMarker || marker.entries.count(entry) || IsStagingName(entry)) continue;
    if (it->is_directory(ec) && fs::is_regular_file(it->path() / kOutputMarker, ec)) continue;  // an output of its own
    foreign.push_back(entry);
  }
  if (ec) fail("cannot list the folder: " + ec.message());
  if (!foreign.empty()) {
    std::sort(foreign.begin(), foreign.end());
    fail("holds " + ListNames(foreign) + ", which rigsim did not write there (its " + std::string(kOutputMarker) +
         " lists what it wrote); move them out of the folder, or choose " + another);
  }
  return {OutputFolderState::kWrittenByRigsim, marker.written_by};
}

void CheckReplaceableOutput(const OutputFolderRequest& request) {
  const OutputFolderState state = CheckOutputFolder(request);
  if (state.kind == OutputFolderState::kWrittenByRigsim && !request.force) {
    const std::string given = request.dir.string();
    throw std::runtime_error((request.option.empty() ? given : request.option + " " + given) +
                             ": already exists (use --force to replace it)");
  }
}

namespace {

// Whether the existing `file` holds what a command of `kind` writes.
bool IsOfKind(const fs::path& file, OutputFileKind kind) {
  std::ifstream in(file, std::ios::binary);
  if (kind == OutputFileKind::kGlb) {
    char magic[4] = {};
    in.read(magic, sizeof magic);
    return in.gcount() == 4 && std::string(magic, 4) == "glTF";
  }
  char c = 0;
  while (in.get(c)) {
    if (!std::isspace(static_cast<unsigned char>(c))) return c == '{';
  }
  return false;
}

const char* KindName(OutputFileKind kind) { return kind == OutputFileKind::kGlb ? "a binary glTF (.glb)" : "a JSON file"; }

}  // namespace

void CheckReplaceableFile(const OutputFileRequest& request) {
  const std::string name = request.option.empty() ? request.file.string() : request.option + " " + request.file.string();
  const std::string another = request.option.empty() ? "another file" : "another " + request.option;
  auto fail = [&](const std::string& why) { throw std::runtime_error(name + ": " + why); };
  if (request.file.empty()) fail("give a file");
  const fs::path file = Resolved(request.file);
  std::error_code ec;
  const fs::file_status status = fs::status(file, ec);
  const bool exists = fs::exists(status);
  if (fs::is_directory(status)) fail("is a folder, not a file; choose " + another + " (a file's name)");
  // Found now rather than when the file is written, after the work and maybe another output.
  if (!fs::is_directory(file.parent_path(), ec)) {
    const fs::path given = request.file.parent_path();
    fail("its folder " + (given.empty() ? file.parent_path() : given).string() + " does not exist; create it, or choose " +
         another);
  }
  for (const CommandInput& input : request.inputs) {
    const fs::path in = Resolved(input.path);
    if (in == file) {
      fail("is " + input.path.string() + ", an input of this command (" + input.what + "); choose " + another);
    }
    if (exists && fs::is_directory(in, ec) && IsWithin(file, in)) {
      fail("lies inside " + input.path.string() + ", an input of this command (" + input.what +
           "), which it may read; choose " + another);
    }
  }
  if (!exists) return;
  if (!fs::is_regular_file(status)) fail("exists and is not a regular file; choose " + another);
  if (!IsOfKind(file, request.kind)) {
    fail(std::string("exists and is not ") + KindName(request.kind) +
         ", what this option writes; rigsim replaces only a file of the kind it writes, --force or not; choose " +
         another);
  }
  if (!request.force) fail("already exists (use --force to replace it)");
}

void CheckDistinctOutputs(const std::vector<std::pair<std::string, fs::path>>& outputs) {
  for (size_t i = 0; i < outputs.size(); ++i) {
    for (size_t j = i + 1; j < outputs.size(); ++j) {
      const auto& [option_a, a] = outputs[i];
      const auto& [option_b, b] = outputs[j];
      if (a.empty() || b.empty() || Resolved(a) != Resolved(b)) continue;
      throw std::runtime_error(option_a + " and " + option_b + " are both " + b.string() +
                               ": the one would replace the other; give each its own file");
    }
  }
}

void WriteOutputMarker(const fs::path& dir, const std::string& written_by, std::vector<std::string> entries) {
  if (entries.empty()) {
    for (const fs::directory_entry& e : fs::directory_iterator(dir)) {
      const std::string name = e.path().filename().string();
      if (name != kOutputMarker) entries.push_back(name);
    }
  }
  std::sort(entries.begin(), entries.end());
  entries.erase(std::unique(entries.begin(), entries.end()), entries.end());
  const json_io::Json marker{{"written_by", written_by}, {"entries", entries}};
  json_io::WriteTextAtomic(dir / kOutputMarker, marker.dump(1) + "\n");
}

namespace {

// Removes staging folders "<parent>/.<name>.partial-<pid>-..." left by runs that were killed
// (SIGKILL, power loss): their process is gone. Folders of live processes are left alone.
void RemoveStaleStaging(const fs::path& final_dir) {
  const fs::path parent = final_dir.parent_path().empty() ? fs::path(".") : final_dir.parent_path();
  std::string prefix = ".";  // (built with += : GCC 12 warns falsely on "." + s + "...")
  prefix += final_dir.filename().string();
  prefix += ".partial-";
  std::error_code ec;
  std::vector<fs::path> stale;
  for (fs::directory_iterator it(parent, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.rfind(prefix, 0) != 0) continue;
    const size_t digits_end = name.find_first_not_of("0123456789", prefix.size());
    if (digits_end == prefix.size()) continue;
    const std::string pid_text = name.substr(prefix.size(), digits_end - prefix.size());
    if (pid_text.size() > 9) continue;
    const pid_t pid = pid_t(std::stol(pid_text));
    if (pid > 0 && ::kill(pid, 0) != 0 && errno == ESRCH) stale.push_back(it->path());
  }
  for (const fs::path& p : stale) fs::remove_all(p, ec);
}

OutputFolderRequest FolderAndForce(fs::path dir, bool force) {
  OutputFolderRequest request;
  request.dir = std::move(dir);
  request.option = "";
  request.force = force;
  return request;
}

}  // namespace

StagedOutput::StagedOutput(fs::path final_dir, bool force) : StagedOutput(FolderAndForce(std::move(final_dir), force)) {}

StagedOutput::StagedOutput(const OutputFolderRequest& request) : final_(request.dir), written_by_(request.written_by) {
  if (final_.filename().empty()) final_ = final_.parent_path();  // "out/" -> "out"
  CheckReplaceableOutput(request);
  RemoveStaleStaging(final_);
  static std::atomic<int> counter{0};
  const auto stamp = std::chrono::steady_clock::now().time_since_epoch().count();
  // Appended piecewise: GCC 12 warns falsely (-Wrestrict) on "literal" + std::string&&.
  std::string name = ".";
  for (const std::string& part : {final_.filename().string(), std::string(".partial-"), std::to_string(::getpid()),
                                  std::string("-"), std::to_string(stamp), std::string("-"),
                                  std::to_string(counter++)}) {
    name += part;
  }
  staging_ = final_.parent_path() / name;
  if (!final_.parent_path().empty()) fs::create_directories(final_.parent_path());
  fs::create_directories(staging_);
}

StagedOutput::~StagedOutput() {
  if (!committed_) {
    std::error_code ec;
    fs::remove_all(staging_, ec);
  }
}

void StagedOutput::Commit() {
  if (committed_) return;
  WriteOutputMarker(staging_, written_by_);
  // Swap the new output with the old one in one atomic step (renameat2 RENAME_EXCHANGE), so that
  // at every instant a complete output sits at `final_`, then drop the old one, now at staging_.
  if (fs::exists(final_)) {
    if (::renameat2(AT_FDCWD, staging_.c_str(), AT_FDCWD, final_.c_str(), RENAME_EXCHANGE) == 0) {
      committed_ = true;
      std::error_code ec;
      fs::remove_all(staging_, ec);
      return;
    }
    // Filesystems without RENAME_EXCHANGE: move the old output aside first. An interruption
    // between the two renames leaves no output (the old one is then a stale staging folder).
    const fs::path old = staging_.string() + ".old";
    fs::rename(final_, old);
    fs::rename(staging_, final_);
    committed_ = true;
    fs::remove_all(old);
    return;
  }
  fs::rename(staging_, final_);
  committed_ = true;
}

}  // namespace rigsim
