// `drape run --export FILE.pc2 / FILE.glb`: animation caches read back and checked against the
// same run's OBJ frames, interrupted runs, and the rules for names and overwriting.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <sstream>
#include <vector>

#include "drape_process.h"
#include "temp_dir.h"

namespace {

namespace fs = std::filesystem;
using drape::testing_support::run_drape;
using drape::testing_support::run_drape_interrupted;
using drape::testing_support::shipped_scene;
using nlohmann::json;

std::vector<char> read_bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

template <typename T>
T at(const std::vector<char>& bytes, size_t offset) {
  T value;
  std::memcpy(&value, bytes.data() + offset, sizeof value);
  return value;
}

// The positions of an OBJ file, in its order.
std::vector<double> obj_positions(const fs::path& file) {
  std::ifstream in(file);
  std::vector<double> xyz;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("v ", 0) != 0) continue;
    std::istringstream ls(line.substr(2));
    double x, y, z;
    ls >> x >> y >> z;
    xyz.insert(xyz.end(), {x, y, z});
  }
  return xyz;
}

// A .glb split into its JSON and its binary chunk, with accessors read as floats.
struct Glb {
  explicit Glb(const fs::path& file) : bytes(read_bytes(file)) {
    if (bytes.size() < 28) return;
    magic = at<uint32_t>(bytes, 0);
    version = at<uint32_t>(bytes, 4);
    length = at<uint32_t>(bytes, 8);
    const uint32_t json_length = at<uint32_t>(bytes, 12);
    json_type = at<uint32_t>(bytes, 16);
    gltf = json::parse(std::string(bytes.data() + 20, json_length));
    bin = 20 + json_length + 8;
    bin_length = at<uint32_t>(bytes, 20 + json_length);
    bin_type = at<uint32_t>(bytes, 20 + json_length + 4);
  }
  // The floats of a float accessor (VEC4, VEC3, VEC2 or SCALAR).
  std::vector<float> floats(int accessor) const {
    const json& a = gltf["accessors"][accessor];
    const json& v = gltf["bufferViews"][a["bufferView"].get<int>()];
    const int components = a["type"] == "VEC4"   ? 4
                           : a["type"] == "VEC3" ? 3
                           : a["type"] == "VEC2" ? 2
                                                 : 1;
    const size_t start = bin + v["byteOffset"].get<size_t>() + a["byteOffset"].get<size_t>();
    std::vector<float> out(a["count"].get<size_t>() * components);
    std::memcpy(out.data(), bytes.data() + start, out.size() * sizeof(float));
    return out;
  }
  std::vector<char> bytes;
  uint32_t magic = 0, version = 0, length = 0, json_type = 0, bin_length = 0, bin_type = 0;
  size_t bin = 0;
  json gltf;
};

class ExportCli : public drape::testing_support::TempDirTest {
 protected:
  ExportCli() : TempDirTest("drape_export_") {}
};

TEST_F(ExportCli, Pc2HeaderAndFramesMatchTheObjFramesOfTheSameRun) {
  const std::string run = "run " + shipped_scene("hang") + " --seconds 0.2 --every 5 --quiet";
  ASSERT_EQ(run_drape(run + " --export " + path("cloth.pc2")).code, 0);
  ASSERT_EQ(run_drape(run + " --export " + path("frames")).code, 0);

  const std::vector<char> pc2 = read_bytes(path("cloth.pc2"));
  ASSERT_GE(pc2.size(), 32u);
  EXPECT_EQ(std::string(pc2.data(), 12), std::string("POINTCACHE2\0", 12));
  EXPECT_EQ(at<int32_t>(pc2, 12), 1);  // version
  EXPECT_EQ(at<int32_t>(pc2, 16), 1024);
  EXPECT_EQ(at<float>(pc2, 20), 0.0f);  // start frame
  EXPECT_EQ(at<float>(pc2, 24), 5.0f);  // sampling: a frame every 5 of the run's
  // 12 frames: 0, 5 and 10. The last, 12, is off the cache's even step, so not in it.
  const int32_t frames = at<int32_t>(pc2, 28);
  EXPECT_EQ(frames, 3);
  EXPECT_EQ(pc2.size(), 32u + size_t(frames) * 1024 * 12);

  for (int k = 0; k < frames; ++k) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%05d.obj", 5 * k);
    const std::vector<double> obj = obj_positions(fs::path(path("frames")) / name);
    ASSERT_EQ(obj.size(), 1024u * 3) << name;
    double worst = 0.0;
    for (size_t i = 0; i < obj.size(); ++i)
      worst = std::max(worst, std::abs(at<float>(pc2, 32 + 4 * (size_t(k) * 3072 + i)) - obj[i]));
    EXPECT_LT(worst, 2e-7) << name;  // float's rounding on coordinates of about 1 m
  }
  // The rest mesh beside it: frame 0, the same vertex order.
  EXPECT_EQ(read_bytes(path("cloth.obj")),
            read_bytes(fs::path(path("frames")) / "frame_00000.obj"));
}

TEST_F(ExportCli, GlbHoldsTheMeshItsFramesAsMorphTargetsAndTheColliders) {
  const std::string run = "run " + shipped_scene("ground") + " --seconds 0.2 --every 5 --quiet";
  ASSERT_EQ(run_drape(run + " --export " + path("run.glb")).code, 0);
  ASSERT_EQ(run_drape(run + " --export " + path("frames")).code, 0);

  const Glb glb(path("run.glb"));
  EXPECT_EQ(glb.magic, 0x46546C67u);  // "glTF"
  EXPECT_EQ(glb.version, 2u);
  EXPECT_EQ(glb.length, glb.bytes.size());
  EXPECT_EQ(glb.json_type, 0x4E4F534Au);  // "JSON"
  EXPECT_EQ(glb.bin_type, 0x004E4942u);   // "BIN"
  EXPECT_EQ(glb.bin + glb.bin_length, glb.bytes.size());
  const json& g = glb.gltf;
  EXPECT_EQ(g["asset"]["version"], "2.0");
  ASSERT_EQ(g["meshes"].size(), 3u);  // the cloth, the sphere, the plane
  EXPECT_EQ(g["meshes"][1]["name"], "sphere 0");
  EXPECT_EQ(g["meshes"][2]["name"], "plane 1");

  // Frames 0 (the mesh), 5, 10 and the last, 12 (targets), at their times.
  const json& cloth = g["meshes"][0]["primitives"][0];
  for (const char* attribute : {"POSITION", "NORMAL", "TEXCOORD_0"})
    EXPECT_TRUE(cloth["attributes"].contains(attribute)) << attribute;
  ASSERT_EQ(cloth["targets"].size(), 3u);
  EXPECT_EQ(g["meshes"][0]["extras"]["targetNames"],
            json({"frame_00005", "frame_00010", "frame_00012"}));
  const json& sampler = g["animations"][0]["samplers"][0];
  const std::vector<float> times = glb.floats(sampler["input"]);
  ASSERT_EQ(times.size(), 4u);
  EXPECT_FLOAT_EQ(times[2], 10 * 0.016666667f);
  EXPECT_FLOAT_EQ(times[3], 12 * 0.016666667f);
  const std::vector<float> weights = glb.floats(sampler["output"]);
  ASSERT_EQ(weights.size(), 4u * 3u);
  EXPECT_EQ(std::vector<float>(weights.begin() + 6, weights.begin() + 9),
            std::vector<float>({0.0f, 1.0f, 0.0f}));  // at frame 10, its target alone

  // Frame 10 is the mesh plus its target's displacements.
  const std::vector<float> base = glb.floats(cloth["attributes"]["POSITION"]);
  const std::vector<float> delta = glb.floats(cloth["targets"][1]["POSITION"]);
  const std::vector<double> obj = obj_positions(fs::path(path("frames")) / "frame_00010.obj");
  ASSERT_EQ(base.size(), obj.size());
  double worst = 0.0;
  for (size_t i = 0; i < obj.size(); ++i)
    worst = std::max(worst, std::abs(base[i] + delta[i] - obj[i]));
  EXPECT_LT(worst, 4e-7);
  EXPECT_EQ(g["meshes"][0]["primitives"][0]["indices"].is_number(), true);
  EXPECT_EQ(g["accessors"][cloth["indices"].get<int>()]["count"], 2 * 31 * 31 * 3);
  // The colliders stand still: the weights are the only channel.
  EXPECT_EQ(g["animations"][0]["channels"].size(), 1u);
}

// A moving collider is animated: the curtain's ball, still until 0.5 s, then 2 m along +z by
// 0.7 s, its node translated so from where its mesh stands (frame 0), never turned.
TEST_F(ExportCli, GlbAnimatesAMovingColliderAlongItsPath) {
  ASSERT_EQ(run_drape("run " + shipped_scene("curtain") +
                      " --seconds 0.8 --every 6 --quiet --export " + path("run.glb"))
                .code,
            0);
  const Glb glb(path("run.glb"));
  const json& g = glb.gltf;
  ASSERT_EQ(g["nodes"][1]["name"], "sphere 0");
  const json& animation = g["animations"][0];
  ASSERT_EQ(animation["channels"].size(), 3u);  // the cloth's weights, the ball's two
  std::vector<float> times, translation, rotation;
  for (const json& channel : animation["channels"]) {
    if (channel["target"]["node"] != 1) continue;
    const json& sampler = animation["samplers"][channel["sampler"].get<int>()];
    times = glb.floats(sampler["input"]);
    (channel["target"]["path"] == "translation" ? translation : rotation) =
        glb.floats(sampler["output"]);
  }
  ASSERT_EQ(translation.size(), 3 * times.size());
  ASSERT_EQ(rotation.size(), 4 * times.size());
  for (size_t k = 0; k < times.size(); ++k) {
    const double z = 2.0 * std::clamp((times[k] - 0.5) / 0.2, 0.0, 1.0);
    EXPECT_NEAR(translation[3 * k], 0.0, 1e-6) << k;
    EXPECT_NEAR(translation[3 * k + 1], 0.0, 1e-6) << k;
    EXPECT_NEAR(translation[3 * k + 2], z, 1e-5) << "at " << times[k] << " s";
    EXPECT_EQ(rotation[4 * k + 3], 1.0f) << k;  // w: no turn
  }
  EXPECT_NEAR(translation.back(), 2.0, 1e-6);
}

TEST_F(ExportCli, InterruptedRunsKeepValidCachesOfTheFramesDone) {
  // A small cloth, so that many frames are done within the second even under the sanitizers.
  for (const char* name : {"run.pc2", "run.glb"}) {
    const int code = run_drape_interrupted("run " + shipped_scene("hang") +
                                               " --set cloth.resolution=[8,8] --seconds 3e4"
                                               " --every 100 --quiet --export " +
                                               path(name),
                                           "INT", 1.0);
    EXPECT_EQ(code, 130) << name;
  }
  const std::vector<char> pc2 = read_bytes(path("run.pc2"));
  ASSERT_GE(pc2.size(), 32u);
  const int32_t frames = at<int32_t>(pc2, 28);
  EXPECT_GT(frames, 1);
  EXPECT_EQ(pc2.size(), 32u + size_t(frames) * 64 * 12);
  EXPECT_EQ(at<float>(pc2, 24), 100.0f);

  const Glb glb(path("run.glb"));
  EXPECT_EQ(glb.length, glb.bytes.size());
  const json& g = glb.gltf;
  const size_t targets = g["meshes"][0]["primitives"][0]["targets"].size();
  EXPECT_GT(targets, 0u);
  EXPECT_EQ(g["accessors"][g["animations"][0]["samplers"][0]["input"].get<int>()]["count"],
            targets + 1);
  // Nothing left under a temporary name.
  for (const auto& entry : fs::directory_iterator(dir_))
    EXPECT_EQ(entry.path().string().find(".tmp"), std::string::npos) << entry.path();
}

TEST_F(ExportCli, AFolderWithPc2OrGlbGetsACacheNamedAfterTheScene) {
  const std::string run = "run " + shipped_scene("hang") + " --seconds 0.05 --quiet --export ";
  ASSERT_EQ(run_drape(run + path("out") + " --format pc2").code, 0);
  ASSERT_EQ(run_drape(run + path("out") + " --format glb").code, 0);
  EXPECT_TRUE(fs::exists(path("out/hang.pc2")));
  EXPECT_TRUE(fs::exists(path("out/hang.obj")));
  EXPECT_TRUE(fs::exists(path("out/hang.glb")));
}

TEST_F(ExportCli, ACacheIsNotOverwrittenUnlessForcedAndTheFormatMustMatchItsName) {
  const std::string run = "run " + shipped_scene("hang") + " --seconds 0.05 --quiet --export ";
  ASSERT_EQ(run_drape(run + path("a.pc2")).code, 0);
  const auto again = run_drape(run + path("a.pc2"));
  EXPECT_EQ(again.code, 2);
  EXPECT_NE(again.output.find("already exists"), std::string::npos) << again.output;
  EXPECT_EQ(run_drape(run + path("a.pc2") + " --force").code, 0);

  const auto mismatch = run_drape(run + path("b.glb") + " --format ply");
  EXPECT_EQ(mismatch.code, 2);
  EXPECT_NE(mismatch.output.find("--format ply: does not match"), std::string::npos)
      << mismatch.output;
  EXPECT_FALSE(fs::exists(path("b.glb")));
}

}  // namespace
