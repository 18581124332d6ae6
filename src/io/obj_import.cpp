#include "io/obj_import.h"

#include <array>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string_view>
#include <vector>

// Linked against tinyobjloader_double, whose target defines TINYOBJLOADER_USE_DOUBLE.
#include <tiny_obj_loader.h>

#include "drape/error.h"

namespace drape::io {

namespace {

[[noreturn]] void fail(const std::string& problem) { throw InputError("", problem); }

[[noreturn]] void fail_at(int line, const std::string& problem) {
  fail("line " + std::to_string(line) + ": " + problem);
}

std::vector<std::string_view> tokens(std::string_view line) {
  std::vector<std::string_view> out;
  size_t k = 0;
  while (k < line.size()) {
    while (k < line.size() && (line[k] == ' ' || line[k] == '\t')) ++k;
    const size_t start = k;
    while (k < line.size() && line[k] != ' ' && line[k] != '\t') ++k;
    if (k > start) out.push_back(line.substr(start, k - start));
  }
  return out;
}

bool number(std::string_view t, double& x) {
  const char* end = t.data() + t.size();
  const char* begin = t.data() + (!t.empty() && t[0] == '+' ? 1 : 0);
  const auto [ptr, ec] = std::from_chars(begin, end, x);
  return ec == std::errc() && ptr == end;
}

bool integer(std::string_view t, long long& k) {
  const char* end = t.data() + t.size();
  const auto [ptr, ec] = std::from_chars(t.data(), end, k);
  return ec == std::errc() && ptr == end;
}

std::string show(std::string_view t) {
  std::string s(t.substr(0, 40));
  if (t.size() > 40) s += "...";
  return "\"" + s + "\"";
}

// The statements of the format that hold nothing for a cloth (groups, materials, smoothing,
// free-form geometry): accepted and ignored.
constexpr std::array<std::string_view, 33> kIgnored = {
    "vn",  "vp",   "l",      "p",    "o",      "g",      "s",      "mg",    "usemtl",
    "mtllib", "maplib", "usemap", "lod", "shadow_obj", "trace_obj", "ctech", "stech", "cstype",
    "deg", "bmat", "step",   "curv", "curv2",  "surf",   "parm",   "trim",  "hole",
    "scrv", "sp",  "end",    "con"};

// The line of every face, in order; checks each statement's form and every index against the
// counts at the end. Throws with the line of the first problem.
std::vector<int32_t> check_lines(const std::string& text) {
  std::vector<int32_t> face_lines;
  struct Ref {
    long long v, t;
    int line;
  };
  std::vector<Ref> refs;
  long long vertices = 0, texcoords = 0;
  std::istringstream in(text);
  std::string raw;
  int line = 0;
  while (std::getline(in, raw)) {
    ++line;
    std::string_view s(raw);
    if (const size_t hash = s.find('#'); hash != std::string_view::npos) s = s.substr(0, hash);
    while (!s.empty() && (s.back() == '\r' || s.back() == ' ' || s.back() == '\t'))
      s.remove_suffix(1);
    // A trailing backslash continues the line: rare, and not worth joining: refused clearly.
    if (!s.empty() && s.back() == '\\') fail_at(line, "a line continued with '\\' is not supported");
    const std::vector<std::string_view> t = tokens(s);
    if (t.empty()) continue;
    const std::string_view key = t[0];
    auto numbers = [&](size_t lo, size_t hi, const char* what) {
      if (t.size() - 1 < lo || t.size() - 1 > hi)
        fail_at(line, std::string("expected ") + what + ", got " + std::to_string(t.size() - 1) +
                          " value(s)");
      for (size_t k = 1; k < t.size(); ++k) {
        double x;
        if (!number(t[k], x)) fail_at(line, show(t[k]) + " is not a number");
        if (!std::isfinite(x)) fail_at(line, show(t[k]) + " is not a finite number");
      }
    };
    if (key == "v") {
      numbers(3, 7, "x y z (and optionally w or r g b)");
      ++vertices;
    } else if (key == "vt") {
      numbers(1, 3, "u (v w)");
      ++texcoords;
    } else if (key == "f") {
      if (t.size() < 4) fail_at(line, "a face needs at least 3 vertices");
      for (size_t k = 1; k < t.size(); ++k) {
        // v, v/t, v//n or v/t/n: non-zero integers, negative counting back from the last.
        std::string_view part[3];
        size_t count = 0, start = 0;
        const std::string_view ref = t[k];
        for (size_t c = 0; c <= ref.size() && count < 4; ++c)
          if (c == ref.size() || ref[c] == '/') {
            if (count < 3) part[count] = ref.substr(start, c - start);
            ++count;
            start = c + 1;
          }
        long long v = 0, vt = 0, vn = 0;
        if (count > 3 || !integer(part[0], v) || v == 0 ||
            (count >= 2 && !part[1].empty() && (!integer(part[1], vt) || vt == 0)) ||
            (count == 3 && !part[2].empty() && (!integer(part[2], vn) || vn == 0)) ||
            (count == 3 && part[2].empty()))
          fail_at(line, show(ref) + " is not a vertex reference (v, v/vt, v//vn or v/vt/vn, "
                                     "each a non-zero integer)");
        // Negative indices count back from the last vertex so far.
        if (v < 0) v += vertices + 1;
        if (vt < 0) vt += texcoords + 1;
        if (v <= 0) fail_at(line, show(ref) + " counts back past the first vertex");
        if (count >= 2 && !part[1].empty() && vt <= 0)
          fail_at(line, show(ref) + " counts back past the first texture coordinate");
        refs.push_back({v, vt, line});
      }
      face_lines.push_back(line);
    } else if (std::find(kIgnored.begin(), kIgnored.end(), key) == kIgnored.end()) {
      fail_at(line, "unknown statement " + show(key));
    }
  }
  for (const Ref& r : refs) {
    if (r.v > vertices)
      fail_at(r.line, "the face names vertex " + std::to_string(r.v) + ", but the file has " +
                          std::to_string(vertices) + " vertices");
    if (r.t > texcoords)
      fail_at(r.line, "the face names texture coordinate " + std::to_string(r.t) +
                          ", but the file has " + std::to_string(texcoords));
  }
  return face_lines;
}

std::string read_file(const std::string& file) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::exists(file, ec)) fail("no such file");
  if (!fs::is_regular_file(file, ec)) fail("not a regular file");
  std::ifstream in(file, std::ios::binary);
  if (!in) fail("cannot be opened for reading");
  std::string text;
  char buffer[1 << 16];
  while (in.read(buffer, sizeof buffer) || in.gcount() > 0) {
    text.append(buffer, static_cast<size_t>(in.gcount()));
    if (static_cast<int64_t>(text.size()) > kMaxObjBytes)
      fail("is larger than " + std::to_string(kMaxObjBytes >> 20) +
           " MiB, far past a cloth the memory budget lets run");
  }
  if (in.bad()) fail("cannot be read");
  return text;
}

}  // namespace

ClothMesh read_obj(const std::string& file) {
  const std::string text = read_file(file);
  const std::vector<int32_t> face_lines = check_lines(text);
  tinyobj::ObjReaderConfig config;
  config.triangulate = false;  // fans below, so that each triangle keeps its face's line
  config.vertex_color = false;
  tinyobj::ObjReader reader;
  // No material text: a `mtllib` names a file, which a cloth has no use for and is not opened.
  if (!reader.ParseFromString(text, "", config)) fail("cannot be read as OBJ: " + reader.Error());
  const tinyobj::attrib_t& a = reader.GetAttrib();
  ClothMesh mesh;
  mesh.positions.reserve(a.vertices.size() / 3);
  for (size_t k = 0; k + 2 < a.vertices.size(); k += 3)
    mesh.positions.emplace_back(a.vertices[k], a.vertices[k + 1], a.vertices[k + 2]);
  for (size_t k = 0; k + 1 < a.texcoords.size(); k += 2)
    mesh.texcoords.emplace_back(a.texcoords[k], a.texcoords[k + 1]);
  bool all_textured = true;
  size_t face = 0;
  for (const tinyobj::shape_t& shape : reader.GetShapes()) {
    size_t at = 0;
    for (const unsigned int corners : shape.mesh.num_face_vertices) {
      const int32_t line = face < face_lines.size() ? face_lines[face] : 0;
      ++face;
      const tinyobj::index_t* idx = shape.mesh.indices.data() + at;
      at += corners;
      for (unsigned int c = 1; c + 1 < corners; ++c) {
        mesh.triangles.push_back({idx[0].vertex_index, idx[c].vertex_index, idx[c + 1].vertex_index});
        mesh.triangle_texcoords.push_back(
            {idx[0].texcoord_index, idx[c].texcoord_index, idx[c + 1].texcoord_index});
        all_textured = all_textured && idx[0].texcoord_index >= 0 && idx[c].texcoord_index >= 0 &&
                       idx[c + 1].texcoord_index >= 0;
        mesh.triangle_line.push_back(line);
      }
    }
  }
  // Lines only if every face was matched to its line (tinyobjloader keeps the file's order).
  if (face != face_lines.size()) mesh.triangle_line.clear();
  if (!all_textured) {
    mesh.texcoords.clear();
    mesh.triangle_texcoords.clear();
  }
  return mesh;
}

}  // namespace drape::io
