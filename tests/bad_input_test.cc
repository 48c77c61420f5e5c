// Bad input through the library readers, one test per kind (issue 6): every error names the file
// and the problem; nothing crashes and nothing allocates more than the input justifies.
// The same inputs through the command line are in cli_errors_test.cc.
#include <sys/resource.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <unistd.h>

#include "dataset/dataset.h"
#include "dataset/image_io.h"
#include "dataset/label_image.h"
#include "geometry/camera_validation.h"
#include "geometry/rig.h"
#include "gltf/gltf_loader.h"
#include "gltf/label_rules.h"
#include "tests/data_uri.h"

namespace rigsim {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

#if defined(__SANITIZE_ADDRESS__)
constexpr bool kAddressSanitizer = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kAddressSanitizer = true;
#else
constexpr bool kAddressSanitizer = false;
#endif
#else
constexpr bool kAddressSanitizer = false;
#endif

// A per-test scratch folder, removed at the end.
class Scratch {
 public:
  Scratch() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = fs::temp_directory_path() / ("rigsim_bad_input_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~Scratch() { fs::remove_all(path_); }
  fs::path operator/(const std::string& name) const { return path_ / name; }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

void WriteBytes(const fs::path& path, const std::vector<uint8_t>& bytes) {
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}
void WriteText(const fs::path& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

// Runs `f`, expects a std::runtime_error whose message starts with `file` and contains `part`.
void ExpectError(const std::function<void()>& f, const std::string& file, const std::string& part) {
  try {
    f();
    ADD_FAILURE() << "no error; expected '" << file << ": ..." << part << "'";
  } catch (const std::runtime_error& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.rfind(file, 0), 0u) << "message does not start with the file name: " << msg;
    EXPECT_NE(msg.find(part), std::string::npos) << "message does not say '" << part << "': " << msg;
  }
}

// A one-triangle glTF whose buffer is a data URI, to be corrupted by each test.
struct Triangle {
  json doc;
  std::vector<uint8_t> bin;
  explicit Triangle(const std::vector<float>& xyz = {0, 0, 0, 1, 0, 0, 0, 1, 0}) {
    bin.resize(xyz.size() * 4);
    std::memcpy(bin.data(), xyz.data(), bin.size());
    doc = {{"asset", {{"version", "2.0"}}},
           {"scene", 0},
           {"scenes", {{{"nodes", {0}}}}},
           {"nodes", {{{"mesh", 0}, {"extras", {{"class", "building"}}}}}},
           {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"mode", 4}}}}}}},
           {"accessors", {{{"bufferView", 0}, {"componentType", 5126}, {"count", xyz.size() / 3}, {"type", "VEC3"}}}},
           {"bufferViews", {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", bin.size()}}}}};
  }
  fs::path Write(const fs::path& path) {
    json d = doc;
    if (!d.contains("buffers")) {
      d["buffers"] = {{{"byteLength", bin.size()}, {"uri", DataUri("application/octet-stream", bin)}}};
    }
    WriteText(path, d.dump(1));
    return path;
  }
};

TEST(BadInput, MissingBufferFileIsNamed) {
  Scratch dir;
  Triangle t;
  t.doc["buffers"] = {{{"byteLength", t.bin.size()}, {"uri", "geometry.bin"}}};  // never written
  const fs::path path = t.Write(dir / "scene.gltf");
  ExpectError([&] { LoadGltf(path); }, path.string(), "geometry.bin");
}

TEST(BadInput, MissingImageFileIsNamed) {
  Scratch dir;
  Triangle t;
  t.doc["images"] = {{{"uri", "facade.png"}}};  // never written
  t.doc["textures"] = {{{"source", 0}}};
  t.doc["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}};
  t.doc["meshes"][0]["primitives"][0]["material"] = 0;
  const fs::path path = t.Write(dir / "scene.gltf");
  ExpectError([&] { LoadGltf(path); }, path.string(), "facade.png");
}

TEST(BadInput, InfiniteVertexIsRejected) {
  Scratch dir;
  Triangle t({0, 0, 0, 1, 0, 0, 0, std::numeric_limits<float>::infinity(), 0});
  const fs::path path = t.Write(dir / "inf.gltf");
  ExpectError([&] { LoadGltf(path); }, path.string(), "vertex 2 is not finite");
}

TEST(BadInput, NonTrianglePrimitivesAreSkippedWithAWarning) {
  Scratch dir;
  Triangle t;
  // The same vertices once more as points and as a line strip: skipped, the triangle stays.
  t.doc["meshes"][0]["primitives"].push_back({{"attributes", {{"POSITION", 0}}}, {"mode", 0}});
  t.doc["meshes"][0]["primitives"].push_back({{"attributes", {{"POSITION", 0}}}, {"mode", 3}});
  const Scene scene = LoadGltf(t.Write(dir / "mixed.gltf"));
  EXPECT_EQ(scene.NumTriangles(), 1u);
  int skipped = 0;
  for (const std::string& w : scene.warnings) skipped += w.find("skipped; only triangles are rendered") != std::string::npos;
  EXPECT_EQ(skipped, 2);
}

// Runs `load` in a forked child whose address space is capped at what it uses now plus 256 MB:
// a loader that trusted a declared count would die of std::bad_alloc there. The child exits 0 when
// `load` throws std::runtime_error containing `part`.
[[noreturn]] void LoadUnderMemoryLimitAndExit(const std::function<void()>& load, const std::string& part) {
  if (!kAddressSanitizer) {  // ASan reserves terabytes of shadow memory: no RLIMIT_AS then
    std::ifstream status("/proc/self/status");
    size_t vm_kb = 0;
    for (std::string line; std::getline(status, line);) {
      if (line.rfind("VmSize:", 0) == 0) vm_kb = std::stoul(line.substr(7));
    }
    const rlim_t limit = rlim_t(vm_kb) * 1024 + (rlim_t(256) << 20);
    const rlimit rl{limit, limit};
    if (vm_kb == 0 || setrlimit(RLIMIT_AS, &rl) != 0) _exit(10);
  }
  try {
    load();
    _exit(11);  // accepted
  } catch (const std::bad_alloc&) {
    _exit(12);
  } catch (const std::runtime_error& e) {
    if (std::string(e.what()).find(part) != std::string::npos) _exit(0);
    std::fprintf(stderr, "unexpected message: %s\n", e.what());
    _exit(13);
  }
}

void ExpectCleanErrorUnderMemoryLimit(const std::function<void()>& load, const std::string& part) {
  EXPECT_EXIT(LoadUnderMemoryLimitAndExit(load, part), ::testing::ExitedWithCode(0), "");
}

TEST(BadInput, AbsurdDeclaredCountsAllocateNothing) {
  Scratch dir;
  {  // 4 billion vertices declared over a 36-byte buffer
    Triangle t;
    t.doc["accessors"][0]["count"] = 4000000000ull;
    const fs::path path = t.Write(dir / "count.gltf");
    ExpectCleanErrorUnderMemoryLimit([&] { LoadGltf(path); }, "exceeds the limit");
  }
  {  // 60 million zero vertices without any bufferView: costs the file nothing
    Triangle t;
    t.doc["accessors"][0].erase("bufferView");
    t.doc["accessors"][0]["count"] = 60000000;
    const fs::path path = t.Write(dir / "zeros.gltf");
    ExpectCleanErrorUnderMemoryLimit([&] { LoadGltf(path); }, "more than the file's buffers hold");
  }
  {  // a bufferView declaring 3 GB of a 36-byte buffer
    Triangle t;
    t.doc["bufferViews"][0]["byteLength"] = 3000000000ull;
    t.doc["accessors"][0]["count"] = 250000000;
    const fs::path path = t.Write(dir / "view.gltf");
    ExpectCleanErrorUnderMemoryLimit([&] { LoadGltf(path); }, path.string());
  }
  {  // a PNG declaring 20000 x 20000 RGBA pixels (1.6 GB) in a few bytes, as a texture and as a label image
    std::vector<uint8_t> png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n', 0, 0, 0, 13, 'I', 'H', 'D', 'R',
                                0, 0, 0x4e, 0x20, 0, 0, 0x4e, 0x20, 8, 6, 0, 0, 0, 0, 0, 0, 0,
                                0, 0, 0, 0, 'I', 'E', 'N', 'D', 0xae, 0x42, 0x60, 0x82};
    Triangle t;
    t.doc["images"] = {{{"uri", DataUri("image/png", png)}}};
    t.doc["textures"] = {{{"source", 0}}};
    t.doc["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}};
    t.doc["meshes"][0]["primitives"][0]["material"] = 0;
    const fs::path path = t.Write(dir / "png.gltf");
    ExpectCleanErrorUnderMemoryLimit([&] { LoadGltf(path); }, path.string());
    WriteBytes(dir / "labels.png", png);
    ExpectCleanErrorUnderMemoryLimit([&] { ReadLabelImage(dir / "labels.png"); }, (dir / "labels.png").string());
  }
  {  // one mesh instanced by many nodes: the total decoded is bounded too
    Triangle t;
    GltfLoadOptions options;
    options.max_accessor_count = 3000;
    json nodes = json::array(), roots = json::array();
    for (int i = 0; i < 1001; ++i) {
      nodes.push_back({{"mesh", 0}});
      roots.push_back(i);
    }
    t.doc["nodes"] = nodes;
    t.doc["scenes"][0]["nodes"] = roots;
    const fs::path path = t.Write(dir / "instances.gltf");
    ExpectError([&] { LoadGltf(path, options); }, path.string(), "accessor elements in total");
  }
}

TEST(BadInput, RigWithImpossibleIntrinsics) {
  Scratch dir;
  auto rig_text = [](const std::string& model, const std::string& params) {
    return R"({"cameras": [{"name": "front", "model": ")" + model + R"(", "width": 640, "height": 480, "params": )" +
           params + "}]}";
  };
  const fs::path negative = dir / "negative.json";
  WriteText(negative, rig_text("PINHOLE", "[-300, 300, 319.5, 239.5]"));
  ExpectError([&] { ReadRig(negative); }, negative.string(), "focal lengths must be positive");

  // k1 = -0.5 folds back 218 px from the centre: the image corners have no ray.
  const fs::path folding = dir / "folding.json";
  WriteText(folding, rig_text("OPENCV", "[400, 400, 319.5, 239.5, -0.5, 0, 0, 0]"));
  const Rig rig = ReadRig(folding);  // possible as a lens...
  ExpectError([&] { CheckRigCoversImages(rig, folding.string()); }, folding.string(),
              "camera 'front': OPENCV distortion cannot be inverted over the 640x480 image");  // ...not for this image

  const fs::path size = dir / "size.json";
  WriteText(size, R"({"cameras": [{"name": "a", "model": "PINHOLE", "width": 4294967297, "height": 480, "params": [1, 1, 0, 0]}]})");
  ExpectError([&] { ReadRig(size); }, size.string(), "image size 4294967297x480");

  const fs::path params = dir / "params.json";
  WriteText(params, rig_text("OPENCV", "[400, 400, 319.5, 239.5]"));
  ExpectError([&] { ReadRig(params); }, params.string(), "OPENCV takes 8 parameters");
}

TEST(BadInput, MalformedJsonEverywhere) {
  Scratch dir;
  const fs::path rig = dir / "rig.json", frames = dir / "frames.json", rules = dir / "rules.json";
  WriteText(rig, R"({"cameras": [{"name": "a", "model": "PINHOLE", "width": 10,)");
  ExpectError([&] { ReadRig(rig); }, rig.string(), "invalid JSON");
  WriteText(rig, R"({"cameras": [{"name": "a", "model": "PINHOLE", "width": "ten", "height": 10, "params": [1, 1, 0, 0]}]})");
  ExpectError([&] { ReadRig(rig); }, rig.string(), "cameras[0].width: must be an integer");
  WriteText(frames, R"({"frames": [{"name": "000000", "rig_from_world": {"rotation_wxyz": [1, 0, 0]}}]})");
  ExpectError([&] { ReadFrames(frames); }, frames.string(), "missing field 'translation'");
  WriteText(frames, "\xff\xfe{}");
  ExpectError([&] { ReadFrames(frames); }, frames.string(), "invalid JSON");
  WriteText(rules, R"({"rules": [{"match": "node", "glob": "Car*", "class": )");
  ExpectError([&] { LabelRules::Read(rules); }, rules.string(), "invalid JSON");
  ExpectError([&] { ReadRig(dir / "absent.json"); }, (dir / "absent.json").string(), "cannot open");
  // Numbers beyond double are a JSON error too (nlohmann throws out_of_range, not parse_error:
  // found by fuzz_rig_json, it escaped the readers and lost the file name).
  WriteText(rig, R"({"cameras": [{"name": "a", "model": "PINHOLE", "width": 10, "height": 10, "params": [1e999, 1, 0, 0]}]})");
  ExpectError([&] { ReadRig(rig); }, rig.string(), "invalid JSON");
  WriteText(frames, R"({"frames": [{"name": "a", "timestamp_s": -1e400}]})");
  ExpectError([&] { ReadFrames(frames); }, frames.string(), "invalid JSON");
  WriteText(rules, R"({"rules": [], "x": 1e999})");
  ExpectError([&] { LabelRules::Read(rules); }, rules.string(), "invalid JSON");
}

TEST(BadInput, MissingTruncatedAndWrongSizeImages) {
  Scratch dir;
  ImageU8 labels(8, 6, 1, 7);  // 7 = road
  WriteImage(dir / "labels.png", labels);
  EXPECT_EQ(ReadLabelImage(dir / "labels.png", 8, 6).at(3, 3), 7);
  ExpectError([&] { ReadLabelImage(dir / "labels.png", 16, 6); }, (dir / "labels.png").string(), "label image is 8x6, expected 16x6");
  ExpectError([&] { ReadImageU8(dir / "nothing.png"); }, (dir / "nothing.png").string(), "no such file");

  std::ifstream in(dir / "labels.png", std::ios::binary);
  std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  bytes.resize(bytes.size() / 2);
  WriteBytes(dir / "truncated.png", bytes);
  ExpectError([&] { ReadLabelImage(dir / "truncated.png"); }, (dir / "truncated.png").string(), "");

  ImageU8 colour(8, 6, 3, 128);  // a colour preview where ids are expected
  WriteImage(dir / "colour.png", colour);
  ExpectError([&] { ReadLabelImage(dir / "colour.png"); }, (dir / "colour.png").string(), "must have 1 channel");
}

TEST(BadInput, LabelImageWithUnknownIds) {
  Scratch dir;
  ImageU8 labels(8, 6, 1, 11);  // building
  labels.at(5, 2) = 200;        // no Cityscapes id
  WriteImage(dir / "labels.png", labels);
  ExpectError([&] { ReadLabelImage(dir / "labels.png"); }, (dir / "labels.png").string(), "pixel (5, 2) has label id 200");
}

TEST(BadInput, StaleStagingFolderOfADeadProcessIsRemoved) {
  Scratch dir;
  // A pid that is certainly dead: a child that has exited and been reaped.
  const pid_t child = fork();
  if (child == 0) _exit(0);
  ASSERT_GT(child, 0);
  int status = 0;
  waitpid(child, &status, 0);
  const fs::path stale = dir / (".out.partial-" + std::to_string(child) + "-1-0");
  const fs::path live = dir / (".out.partial-" + std::to_string(::getpid()) + "-1-0");  // our own: alive
  const fs::path other = dir / (".other.partial-" + std::to_string(child) + "-1-0");   // another output's
  for (const fs::path& p : {stale, live, other}) fs::create_directories(p / "images");
  {
    StagedOutput staged(dir / "out", false);
    EXPECT_FALSE(fs::exists(stale));
    EXPECT_TRUE(fs::exists(live));
    EXPECT_TRUE(fs::exists(other));
  }
  fs::remove_all(live);
}

}  // namespace
}  // namespace rigsim
