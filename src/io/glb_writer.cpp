#include "io/glb_writer.h"

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <tuple>

#include <nlohmann/json.hpp>

#include "io/collider_mesh.h"
#include "io/output_file.h"

namespace drape::io {

static_assert(std::endian::native == std::endian::little, "glTF writer assumes little endian");

using nlohmann::json;

namespace {

// glTF's numbers for component types, buffer view targets and the GLB container.
constexpr int kFloat = 5126, kUnsignedInt = 5125;
constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;
constexpr uint32_t kMagic = 0x46546C67, kJsonChunk = 0x4E4F534A, kBinChunk = 0x004E4942;

size_t padded(size_t bytes) {
  return (bytes + 3) & ~size_t{3};
}

OutputError write_error(const std::string& file) {
  return OutputError(file + ": cannot write: " + std::strerror(errno));
}

// A unit normal in single precision: normalised after rounding, as the validator checks it.
std::array<float, 3> unit_normal(const Vec3& n) {
  std::array<float, 3> f{static_cast<float>(n.x()), static_cast<float>(n.y()),
                         static_cast<float>(n.z())};
  const float len = std::sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
  if (!(len > 0.0f) || !std::isfinite(len)) return {0.0f, 1.0f, 0.0f};  // no area around it
  for (float& c : f) c /= len;
  return f;
}

// min and max per component of float triples.
std::array<float, 6> bounds(const float* xyz, size_t count) {
  std::array<float, 6> b{};
  b.fill(0.0f);
  for (int k = 0; k < 3; ++k) {
    b[k] = std::numeric_limits<float>::infinity();
    b[3 + k] = -std::numeric_limits<float>::infinity();
  }
  for (size_t i = 0; i < count; ++i)
    for (int k = 0; k < 3; ++k) {
      b[k] = std::min(b[k], xyz[3 * i + k]);
      b[3 + k] = std::max(b[3 + k], xyz[3 * i + k]);
    }
  return b;
}

// The JSON's buffer views and accessors, over one binary buffer.
struct Layout {
  json views = json::array();
  json accessors = json::array();

  int view(size_t offset, size_t length, int target = 0, int stride = 0) {
    json v{{"buffer", 0}, {"byteOffset", offset}, {"byteLength", length}};
    if (target) v["target"] = target;
    if (stride) v["byteStride"] = stride;
    views.push_back(v);
    return static_cast<int>(views.size()) - 1;
  }
  int accessor(int view, size_t offset, int component, size_t count, const char* type) {
    accessors.push_back({{"bufferView", view},
                         {"byteOffset", offset},
                         {"componentType", component},
                         {"count", count},
                         {"type", type}});
    return static_cast<int>(accessors.size()) - 1;
  }
  int vec3(int view, size_t offset, size_t count, const std::array<float, 6>* b = nullptr) {
    const int a = accessor(view, offset, kFloat, count, "VEC3");
    if (b) {
      accessors[a]["min"] = {(*b)[0], (*b)[1], (*b)[2]};
      accessors[a]["max"] = {(*b)[3], (*b)[4], (*b)[5]};
    }
    return a;
  }
};

// Binary data that is small enough to hold: appended 4-byte aligned, placed at `origin` in the
// buffer.
struct Block {
  size_t origin = 0;
  std::vector<unsigned char> bytes;
  size_t append(const void* data, size_t size) {
    const size_t at = bytes.size();
    bytes.resize(padded(at + size), 0);
    std::memcpy(bytes.data() + at, data, size);
    return origin + at;
  }
};

}  // namespace

GlbWriter::GlbWriter(std::string file, std::string name, std::string generator,
                     const ClothModel& model, const ClothState& first, double time,
                     const std::vector<Collider>& colliders)
    : file_(std::move(file)),
      name_(std::move(name)),
      generator_(std::move(generator)),
      x0_(first.x),
      colliders_(colliders) {
  const size_t n = x0_.size();
  position0_.resize(3 * n);
  normal0_.resize(3 * n);
  uv_.resize(2 * n);
  for (size_t i = 0; i < n; ++i) {
    const std::array<float, 3> u = unit_normal(first.normal[i]);
    for (int k = 0; k < 3; ++k) {
      position0_[3 * i + k] = static_cast<float>(x0_[i][k]);
      normal0_[3 * i + k] = u[k];
    }
    uv_[2 * i] = static_cast<float>(model.uv[i].x());
    uv_[2 * i + 1] = static_cast<float>(model.uv[i].y());
  }
  for (const Triangle& t : model.triangles)
    for (int32_t v : t) indices_.push_back(static_cast<uint32_t>(v));
  delta_.resize(6 * n);
  times_.push_back(static_cast<float>(time));
  for (size_t c = 0; c < colliders_.size(); ++c) tracks_.push_back({0, 0, 0, 0, 0, 0, 1});

  // Planes are drawn as squares ten times the cloth's size around its start.
  Vec3 lo = x0_.empty() ? Vec3::Zero() : x0_[0], hi = lo;
  for (const Vec3& x : x0_) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
  focus_ = 0.5 * (lo + hi);
  extent_ = 10.0 * std::max(1.0, (hi - lo).norm());

  // Opened and at once unlinked: the space goes back to the system however the run ends.
  const std::string scratch = file_ + ".frames.tmp";
  scratch_ = std::fopen(scratch.c_str(), "w+b");
  if (!scratch_) throw write_error(file_);
  std::remove(scratch.c_str());
}

GlbWriter::~GlbWriter() {
  if (scratch_) std::fclose(scratch_);
}

void GlbWriter::add_frame(const ClothState& state, int64_t frame, double time,
                          const std::vector<Collider>& colliders) {
  const size_t n = x0_.size();
  if (state.x.size() != n)
    throw std::logic_error(file_ + ": a frame of " + std::to_string(state.x.size()) +
                           " points in a mesh of " + std::to_string(n));
  // Positions, then normals, each relative to frame 0 as stored.
  for (size_t i = 0; i < n; ++i) {
    const std::array<float, 3> u = unit_normal(state.normal[i]);
    for (int k = 0; k < 3; ++k) {
      delta_[3 * i + k] = static_cast<float>(state.x[i][k] - x0_[i][k]);
      delta_[3 * (n + i) + k] = u[k] - normal0_[3 * i + k];
    }
  }
  target_bounds_.push_back(bounds(delta_.data(), n));
  write_all(scratch_, delta_.data(), delta_.size() * sizeof(float), file_);
  times_.push_back(static_cast<float>(time));
  // Each collider's pose now relative to frame 0's: R·R0ᵀ, and t − R·R0ᵀ·t0.
  const size_t last = tracks_.size() - colliders_.size();
  for (size_t c = 0; c < colliders_.size(); ++c) {
    if (colliders.size() != colliders_.size()) {
      tracks_.push_back(tracks_[last + c]);
      continue;
    }
    const Pose& p0 = colliders_[c].pose;
    const Pose& p = colliders[c].pose;
    const Mat3 turn = p.rotation * p0.rotation.transpose();
    const Vec3 move = p.translation - turn * p0.translation;
    const Eigen::Quaterniond q(turn);
    tracks_.push_back({static_cast<float>(move.x()), static_cast<float>(move.y()),
                       static_cast<float>(move.z()), static_cast<float>(q.x()),
                       static_cast<float>(q.y()), static_cast<float>(q.z()),
                       static_cast<float>(q.w())});
  }
  char name[32];
  std::snprintf(name, sizeof name, "frame_%05lld", static_cast<long long>(frame));
  target_names_.push_back(name);
}

double GlbWriter::estimated_bytes(int64_t particles, int64_t triangles, int64_t frames) {
  const double n = static_cast<double>(particles), k = static_cast<double>(frames);
  const double targets = std::max(0.0, k - 1.0);
  const double text = 4096.0 + 400.0 * targets;  // the fixed part, two accessors per target
  const double mesh = 32.0 * n + 12.0 * static_cast<double>(triangles);
  const double colliders = 64.0 * 1024.0;  // generous for a few spheres and planes
  return text + mesh + colliders + 24.0 * n * targets + 4.0 * k * targets;
}

void GlbWriter::finish() {
  const size_t n = x0_.size();
  const size_t targets = target_bounds_.size();
  const size_t keys = times_.size();
  const size_t frame_bytes = n * 6 * sizeof(float);
  Layout layout;

  // The morph targets first, as they lie in the scratch file: one view, a stride of one vector.
  const size_t targets_bytes = targets * frame_bytes;
  json target_list = json::array();
  if (targets > 0) {
    const int view = layout.view(0, targets_bytes, kArrayBuffer, 12);
    for (size_t t = 0; t < targets; ++t) {
      const int position = layout.vec3(view, t * frame_bytes, n, &target_bounds_[t]);
      const int normal = layout.vec3(view, t * frame_bytes + n * 12, n);
      target_list.push_back({{"POSITION", position}, {"NORMAL", normal}});
    }
  }

  // Then what is held: the cloth's base mesh, the colliders' meshes, the keyframe times.
  Block held;
  held.origin = targets_bytes;
  auto floats = [&](const std::vector<float>& v, int components) {
    const size_t at = held.append(v.data(), v.size() * sizeof(float));
    return std::pair{at, v.size() / components};
  };
  auto vec3_attribute = [&](const std::vector<float>& v, bool with_bounds) {
    const auto [at, count] = floats(v, 3);
    const std::array<float, 6> b = bounds(v.data(), count);
    return layout.vec3(layout.view(at, count * 12, kArrayBuffer), 0, count,
                       with_bounds ? &b : nullptr);
  };
  auto index_accessor = [&](const std::vector<uint32_t>& idx) {
    const size_t at = held.append(idx.data(), idx.size() * sizeof(uint32_t));
    return layout.accessor(layout.view(at, idx.size() * 4, kElementArrayBuffer), 0, kUnsignedInt,
                           idx.size(), "SCALAR");
  };

  json attributes{{"POSITION", vec3_attribute(position0_, true)},
                  {"NORMAL", vec3_attribute(normal0_, false)}};
  {
    const auto [at, count] = floats(uv_, 2);
    attributes["TEXCOORD_0"] =
        layout.accessor(layout.view(at, count * 8, kArrayBuffer), 0, kFloat, count, "VEC2");
  }
  json cloth_primitive{{"attributes", attributes},
                       {"indices", index_accessor(indices_)},
                       {"material", 0},
                       {"mode", 4}};
  json cloth_mesh{{"name", name_}, {"primitives", json::array()}};
  if (targets > 0) {
    cloth_primitive["targets"] = target_list;
    cloth_mesh["weights"] = std::vector<float>(targets, 0.0f);
    // Blender and three.js name shape keys and morph targets from this.
    cloth_mesh["extras"] = {{"targetNames", target_names_}};
  }
  cloth_mesh["primitives"].push_back(cloth_primitive);

  json meshes = json::array({cloth_mesh});
  json nodes = json::array({{{"name", name_}, {"mesh", 0}}});
  for (size_t c = 0; c < colliders_.size(); ++c) {
    const SurfaceMesh m = collider_mesh(colliders_[c], focus_, extent_);
    std::vector<float> p, nn;
    std::vector<uint32_t> idx;
    for (size_t i = 0; i < m.position.size(); ++i)
      for (int k = 0; k < 3; ++k) {
        p.push_back(static_cast<float>(m.position[i][k]));
        nn.push_back(static_cast<float>(m.normal[i][k]));
      }
    for (const auto& t : m.triangles)
      for (int32_t v : t) idx.push_back(static_cast<uint32_t>(v));
    const std::string name = std::string(to_string(colliders_[c].type)) + " " + std::to_string(c);
    meshes.push_back(
        {{"name", name},
         {"primitives",
          {{{"attributes",
             {{"POSITION", vec3_attribute(p, true)}, {"NORMAL", vec3_attribute(nn, false)}}},
            {"indices", index_accessor(idx)},
            {"material", 1},
            {"mode", 4}}}}});
    nodes.push_back({{"name", name}, {"mesh", meshes.size() - 1}});
  }

  json animations = json::array();
  size_t weights_origin = targets_bytes + held.bytes.size();
  size_t weights_bytes = 0;
  if (targets > 0) {
    const size_t at = held.append(times_.data(), keys * sizeof(float));
    const int input = layout.accessor(layout.view(at, keys * 4), 0, kFloat, keys, "SCALAR");
    layout.accessors[input]["min"] = {times_.front()};
    layout.accessors[input]["max"] = {times_.back()};
    weights_bytes = keys * targets * sizeof(float);
    // The weights' sampler gets its output below, once the weights' place is known.
    json channels = {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "weights"}}}}};
    json samplers = {{{"input", input}, {"interpolation", "LINEAR"}}};
    // The colliders that move: their translations and rotations (slerped) at the same times.
    const size_t count = colliders_.size();
    for (size_t c = 0; c < count; ++c) {
      bool moves = false;
      for (size_t k = 1; k < keys; ++k) moves = moves || tracks_[k * count + c] != tracks_[c];
      if (!moves) continue;
      std::vector<float> translation, rotation;
      for (size_t k = 0; k < keys; ++k) {
        const std::array<float, 7>& t = tracks_[k * count + c];
        translation.insert(translation.end(), t.begin(), t.begin() + 3);
        rotation.insert(rotation.end(), t.begin() + 3, t.end());
      }
      for (const auto& [values, type, path] :
           {std::tuple{&translation, "VEC3", "translation"}, {&rotation, "VEC4", "rotation"}}) {
        const size_t track = held.append(values->data(), values->size() * sizeof(float));
        const int out = layout.accessor(layout.view(track, values->size() * sizeof(float)), 0,
                                        kFloat, keys, type);
        channels.push_back(
            {{"sampler", samplers.size()}, {"target", {{"node", c + 1}, {"path", path}}}});
        samplers.push_back({{"input", input}, {"output", out}, {"interpolation", "LINEAR"}});
      }
    }
    weights_origin = targets_bytes + held.bytes.size();
    const int output = layout.accessor(layout.view(weights_origin, weights_bytes), 0, kFloat,
                                       keys * targets, "SCALAR");
    samplers[0]["output"] = output;
    animations.push_back({{"name", name_}, {"channels", channels}, {"samplers", samplers}});
  }

  const size_t bin_bytes = padded(weights_origin + weights_bytes);
  json gltf{{"asset", {{"version", "2.0"}, {"generator", generator_}}},
            {"scene", 0},
            {"scenes", {{{"nodes", json::array()}}}},
            {"nodes", nodes},
            {"meshes", meshes},
            {"materials",
             {{{"name", "cloth"},
               {"doubleSided", true},
               {"pbrMetallicRoughness",
                {{"baseColorFactor", {0.80, 0.22, 0.18, 1.0}},
                 {"metallicFactor", 0.0},
                 {"roughnessFactor", 0.85}}}}}},
            {"accessors", layout.accessors},
            {"bufferViews", layout.views},
            {"buffers", {{{"byteLength", bin_bytes}}}}};
  for (size_t i = 0; i < nodes.size(); ++i) gltf["scenes"][0]["nodes"].push_back(i);
  if (!colliders_.empty())
    gltf["materials"].push_back({{"name", "collider"},
                                 {"pbrMetallicRoughness",
                                  {{"baseColorFactor", {0.60, 0.62, 0.66, 1.0}},
                                   {"metallicFactor", 0.0},
                                   {"roughnessFactor", 0.6}}}});
  if (!animations.empty()) gltf["animations"] = animations;

  std::string text = gltf.dump();
  text.resize(padded(text.size()), ' ');  // the JSON chunk is padded with spaces
  const double total =
      12.0 + 8.0 + static_cast<double>(text.size()) + 8.0 + static_cast<double>(bin_bytes);
  if (total > kMaxBytes)
    throw OutputError(file_ + ": " + std::to_string(keys) + " frames of " + std::to_string(n) +
                      " vertices pass the 4 GiB a .glb can hold; export fewer frames "
                      "with --every");

  OutputFile out(file_);
  FILE* f = out.get();
  const uint32_t header[5] = {kMagic, 2, static_cast<uint32_t>(total),
                              static_cast<uint32_t>(text.size()), kJsonChunk};
  write_all(f, header, sizeof header, file_);
  write_all(f, text.data(), text.size(), file_);
  const uint32_t bin_header[2] = {static_cast<uint32_t>(bin_bytes), kBinChunk};
  write_all(f, bin_header, sizeof bin_header, file_);

  // The targets, copied from the scratch file.
  if (std::fflush(scratch_) != 0 || std::fseek(scratch_, 0, SEEK_SET) != 0)
    throw write_error(file_);
  std::vector<unsigned char> chunk(1 << 20);
  for (size_t left = targets_bytes; left > 0;) {
    const size_t want = std::min(left, chunk.size());
    if (std::fread(chunk.data(), 1, want, scratch_) != want) throw write_error(file_);
    write_all(f, chunk.data(), want, file_);
    left -= want;
  }
  write_all(f, held.bytes.data(), held.bytes.size(), file_);
  // The weights: at keyframe k, target k − 1 at 1 and every other at 0.
  std::vector<float> row(targets, 0.0f);
  for (size_t k = 0; k < keys && targets > 0; ++k) {
    if (k > 0) row[k - 1] = 1.0f;
    write_all(f, row.data(), targets * sizeof(float), file_);
    if (k > 0) row[k - 1] = 0.0f;
  }
  const size_t written = weights_origin + weights_bytes;
  const unsigned char zeros[4] = {0, 0, 0, 0};
  write_all(f, zeros, bin_bytes - written, file_);
  out.commit();
}

}  // namespace drape::io
