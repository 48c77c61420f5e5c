// Bad input through the library readers, one test per kind: every error names the file
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

#include <gmock/gmock.h>
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
#include "testing/expect_error.h"
#include "testing/gltf_builder.h"
#include "testing/temp_dir.h"

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

void WriteBytes(const fs::path& path, const std::vector<uint8_t>& bytes) {
  WriteFile(path, std::string(bytes.begin(), bytes.end()));
}

// Every error is a std::runtime_error whose message starts with the file's name.
using Error = std::runtime_error;

// A one-triangle glTF whose buffer is a data URI, to be corrupted by each test.
GltfBuilder Triangle(const std::vector<float>& xyz = {0, 0, 0, 1, 0, 0, 0, 1, 0}) {
  GltfBuilder g;
  g.Triangle(xyz, "building");
  return g;
}

TEST(BadInput, MissingBufferFileIsNamed) {
  const TempDir dir;
  GltfBuilder t = Triangle();
  t.doc["buffers"] = {{{"byteLength", t.bin.size()}, {"uri", "geometry.bin"}}};  // never written
  const fs::path path = t.WriteEmbedded(dir, "scene");
  EXPECT_THAT([&] { LoadGltf(path); }, ThrowsNaming<Error>(path, "geometry.bin"));
}

TEST(BadInput, MissingImageFileIsNamed) {
  const TempDir dir;
  GltfBuilder t = Triangle();
  t.doc["images"] = {{{"uri", "facade.png"}}};  // never written
  t.doc["textures"] = {{{"source", 0}}};
  t.doc["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}};
  t.doc["meshes"][0]["primitives"][0]["material"] = 0;
  const fs::path path = t.WriteEmbedded(dir, "scene");
  EXPECT_THAT([&] { LoadGltf(path); }, ThrowsNaming<Error>(path, "facade.png"));
}

TEST(BadInput, InfiniteVertexIsRejected) {
  const TempDir dir;
  GltfBuilder t = Triangle({0, 0, 0, 1, 0, 0, 0, std::numeric_limits<float>::infinity(), 0});
  const fs::path path = t.WriteEmbedded(dir, "inf");
  EXPECT_THAT([&] { LoadGltf(path); }, ThrowsNaming<Error>(path, "vertex 2 is not finite"));
}

TEST(BadInput, NonTrianglePrimitivesAreSkippedWithAWarning) {
  const TempDir dir;
  GltfBuilder t = Triangle();
  // The same vertices once more as points and as a line strip: skipped, the triangle stays.
  t.doc["meshes"][0]["primitives"].push_back({{"attributes", {{"POSITION", 0}}}, {"mode", 0}});
  t.doc["meshes"][0]["primitives"].push_back({{"attributes", {{"POSITION", 0}}}, {"mode", 3}});
  const Scene scene = LoadGltf(t.WriteEmbedded(dir, "mixed"));
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
  const TempDir dir;
  {  // 4 billion vertices declared over a 36-byte buffer
    GltfBuilder t = Triangle();
    t.doc["accessors"][0]["count"] = 4000000000ull;
    const fs::path path = t.WriteEmbedded(dir, "count");
    ExpectCleanErrorUnderMemoryLimit([&] { LoadGltf(path); }, "exceeds the limit");
  }
  {  // 60 million zero vertices without any bufferView: costs the file nothing
    GltfBuilder t = Triangle();
    t.doc["accessors"][0].erase("bufferView");
    t.doc["accessors"][0]["count"] = 60000000;
    const fs::path path = t.WriteEmbedded(dir, "zeros");
    ExpectCleanErrorUnderMemoryLimit([&] { LoadGltf(path); }, "more than the file's buffers hold");
  }
  {  // a bufferView declaring 3 GB of a 36-byte buffer
    GltfBuilder t = Triangle();
    t.doc["bufferViews"][0]["byteLength"] = 3000000000ull;
    t.doc["accessors"][0]["count"] = 250000000;
    const fs::path path = t.WriteEmbedded(dir, "view");
    ExpectCleanErrorUnderMemoryLimit([&] { LoadGltf(path); }, path.string());
  }
  {  // a PNG declaring 20000 x 20000 RGBA pixels (1.6 GB) in a few bytes, as a texture and as a label image
    std::vector<uint8_t> png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n', 0, 0, 0, 13, 'I', 'H', 'D', 'R',
                                0, 0, 0x4e, 0x20, 0, 0, 0x4e, 0x20, 8, 6, 0, 0, 0, 0, 0, 0, 0,
                                0, 0, 0, 0, 'I', 'E', 'N', 'D', 0xae, 0x42, 0x60, 0x82};
    GltfBuilder t = Triangle();
    t.doc["images"] = {{{"uri", DataUri("image/png", png)}}};
    t.doc["textures"] = {{{"source", 0}}};
    t.doc["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}};
    t.doc["meshes"][0]["primitives"][0]["material"] = 0;
    const fs::path path = t.WriteEmbedded(dir, "png");
    ExpectCleanErrorUnderMemoryLimit([&] { LoadGltf(path); }, path.string());
    WriteBytes(dir / "labels.png", png);
    ExpectCleanErrorUnderMemoryLimit([&] { ReadLabelImage(dir / "labels.png"); }, (dir / "labels.png").string());
  }
  {  // one mesh instanced by many nodes: the total decoded is bounded too
    GltfBuilder t = Triangle();
    GltfLoadOptions options;
    options.max_accessor_count = 3000;
    json nodes = json::array(), roots = json::array();
    for (int i = 0; i < 1001; ++i) {
      nodes.push_back({{"mesh", 0}});
      roots.push_back(i);
    }
    t.doc["nodes"] = nodes;
    t.doc["scenes"][0]["nodes"] = roots;
    const fs::path path = t.WriteEmbedded(dir, "instances");
    EXPECT_THAT([&] { LoadGltf(path, options); }, ThrowsNaming<Error>(path, "accessor elements in total"));
  }
}

TEST(BadInput, RigWithImpossibleIntrinsics) {
  const TempDir dir;
  auto rig_text = [](const std::string& model, const std::string& params) {
    return R"({"cameras": [{"name": "front", "model": ")" + model + R"(", "width": 640, "height": 480, "params": )" +
           params + "}]}";
  };
  const fs::path negative = dir / "negative.json";
  WriteFile(negative, rig_text("PINHOLE", "[-300, 300, 319.5, 239.5]"));
  EXPECT_THAT([&] { ReadRig(negative); }, ThrowsNaming<Error>(negative, "focal lengths must be positive"));

  // k1 = -0.5 folds back 218 px from the centre: the image corners have no ray.
  const fs::path folding = dir / "folding.json";
  WriteFile(folding, rig_text("OPENCV", "[400, 400, 319.5, 239.5, -0.5, 0, 0, 0]"));
  const Rig rig = ReadRig(folding);  // possible as a lens, not for this image:
  EXPECT_THAT([&] { CheckRigCoversImages(rig, folding.string()); },
              ThrowsNaming<Error>(folding, "camera 'front': OPENCV distortion cannot be inverted over the 640x480 image"));

  const fs::path size = dir / "size.json";
  WriteFile(size, R"({"cameras": [{"name": "a", "model": "PINHOLE", "width": 4294967297, "height": 480, "params": [1, 1, 0, 0]}]})");
  EXPECT_THAT([&] { ReadRig(size); }, ThrowsNaming<Error>(size, "image size 4294967297x480"));

  const fs::path params = dir / "params.json";
  WriteFile(params, rig_text("OPENCV", "[400, 400, 319.5, 239.5]"));
  EXPECT_THAT([&] { ReadRig(params); }, ThrowsNaming<Error>(params, "OPENCV takes 8 parameters"));
}

TEST(BadInput, MalformedJsonEverywhere) {
  const TempDir dir;
  const fs::path rig = dir / "rig.json", frames = dir / "frames.json", rules = dir / "rules.json";
  WriteFile(rig, R"({"cameras": [{"name": "a", "model": "PINHOLE", "width": 10,)");
  EXPECT_THAT([&] { ReadRig(rig); }, ThrowsNaming<Error>(rig, "invalid JSON"));
  WriteFile(rig, R"({"cameras": [{"name": "a", "model": "PINHOLE", "width": "ten", "height": 10, "params": [1, 1, 0, 0]}]})");
  EXPECT_THAT([&] { ReadRig(rig); }, ThrowsNaming<Error>(rig, "cameras[0].width: must be an integer"));
  WriteFile(frames, R"({"frames": [{"name": "000000", "rig_from_world": {"rotation_wxyz": [1, 0, 0]}}]})");
  EXPECT_THAT([&] { ReadFrames(frames); }, ThrowsNaming<Error>(frames, "missing field 'translation'"));
  WriteFile(frames, "\xff\xfe{}");
  EXPECT_THAT([&] { ReadFrames(frames); }, ThrowsNaming<Error>(frames, "invalid JSON"));
  WriteFile(rules, R"({"rules": [{"match": "node", "glob": "Car*", "class": )");
  EXPECT_THAT([&] { LabelRules::Read(rules); }, ThrowsNaming<Error>(rules, "invalid JSON"));
  EXPECT_THAT([&] { ReadRig(dir / "absent.json"); }, ThrowsNaming<Error>(dir / "absent.json", "cannot open"));
  // Numbers beyond double are a JSON error too (nlohmann throws out_of_range, not parse_error:
  // found by fuzz_rig_json, it escaped the readers and lost the file name).
  WriteFile(rig, R"({"cameras": [{"name": "a", "model": "PINHOLE", "width": 10, "height": 10, "params": [1e999, 1, 0, 0]}]})");
  EXPECT_THAT([&] { ReadRig(rig); }, ThrowsNaming<Error>(rig, "invalid JSON"));
  WriteFile(frames, R"({"frames": [{"name": "a", "timestamp_s": -1e400}]})");
  EXPECT_THAT([&] { ReadFrames(frames); }, ThrowsNaming<Error>(frames, "invalid JSON"));
  WriteFile(rules, R"({"rules": [], "x": 1e999})");
  EXPECT_THAT([&] { LabelRules::Read(rules); }, ThrowsNaming<Error>(rules, "invalid JSON"));
}

TEST(BadInput, MissingTruncatedAndWrongSizeImages) {
  const TempDir dir;
  ImageU8 labels(8, 6, 1, 7);  // 7 = road
  WriteImage(dir / "labels.png", labels);
  EXPECT_EQ(ReadLabelImage(dir / "labels.png", 8, 6).at(3, 3), 7);
  EXPECT_THAT([&] { ReadLabelImage(dir / "labels.png", 16, 6); },
              ThrowsNaming<Error>(dir / "labels.png", "label image is 8x6, expected 16x6"));
  EXPECT_THAT([&] { ReadImageU8(dir / "nothing.png"); }, ThrowsNaming<Error>(dir / "nothing.png", "no such file"));

  std::ifstream in(dir / "labels.png", std::ios::binary);
  std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  bytes.resize(bytes.size() / 2);
  WriteBytes(dir / "truncated.png", bytes);
  EXPECT_THAT([&] { ReadLabelImage(dir / "truncated.png"); }, ThrowsNaming<Error>(dir / "truncated.png", ""));

  ImageU8 colour(8, 6, 3, 128);  // a colour preview where ids are expected
  WriteImage(dir / "colour.png", colour);
  EXPECT_THAT([&] { ReadLabelImage(dir / "colour.png"); },
              ThrowsNaming<Error>(dir / "colour.png", "must have 1 channel"));
}

TEST(BadInput, LabelImageWithUnknownIds) {
  const TempDir dir;
  ImageU8 labels(8, 6, 1, 11);  // building
  labels.at(5, 2) = 200;        // no Cityscapes id
  WriteImage(dir / "labels.png", labels);
  EXPECT_THAT([&] { ReadLabelImage(dir / "labels.png"); },
              ThrowsNaming<Error>(dir / "labels.png", "pixel (5, 2) has label id 200"));
}

TEST(BadInput, StaleStagingFolderOfADeadProcessIsRemoved) {
  const TempDir dir;
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
