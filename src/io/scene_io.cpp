#include "io/scene_io.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <sstream>

#include "drape/error.h"
#include "io/obj_import.h"
#include "io/shown_text.h"

namespace drape::io {

using nlohmann::json;

namespace {

// JSON text for messages, cut to a readable length. Replaces invalid UTF-8 (a bare-word --set
// value can hold any bytes) instead of throwing.
std::string show(const json& j) {
  return shown(j.dump(-1, ' ', false, json::error_handler_t::replace), 57);
}

std::string type_name(const json& j) {
  if (j.is_number_integer()) return "an integer";
  if (j.is_number()) return "a number";
  if (j.is_string()) return "a string " + show(j);
  if (j.is_boolean()) return show(j);
  if (j.is_null()) return "null";
  if (j.is_array()) return "an array";
  return "an object";
}

[[noreturn]] void fail(const std::string& path, const std::string& problem) {
  throw InputError(path, problem);
}

// Levenshtein distance, for "did you mean" hints.
size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diag = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

std::string list(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

// Reads one JSON object, remembering which keys were asked for so that finish() can name the
// ones nobody knows, with the nearest known name.
class Reader {
 public:
  Reader(const json& j, std::string path) : j_(j), path_(std::move(path)) {
    if (!j_.is_object())
      fail(path_.empty() ? "(top level)" : path_, "expected an object, got " + type_name(j_));
  }

  std::string at(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }

  const json* find(const std::string& key) {
    known_.push_back(key);
    auto it = j_.find(key);
    return it == j_.end() ? nullptr : &*it;
  }

  void number(const std::string& key, double& out) {
    if (const json* v = find(key)) out = as_number(*v, at(key));
  }
  void number(const std::string& key, std::optional<double>& out) {
    if (const json* v = find(key)) out = as_number(*v, at(key));
  }
  void integer(const std::string& key, int& out) {
    if (const json* v = find(key)) out = as_integer(*v, at(key));
  }
  void vec3(const std::string& key, Vec3& out) {
    if (const json* v = find(key)) out = as_vec3(*v, at(key));
  }
  void string(const std::string& key, std::string& out) {
    if (const json* v = find(key)) {
      if (!v->is_string()) fail(at(key), "expected a string, got " + type_name(*v));
      out = v->get<std::string>();
    }
  }
  template <class Enum>
  void choice(const std::string& key, Enum& out, const std::vector<Enum>& options) {
    const json* v = find(key);
    if (!v) return;
    if (!v->is_string()) fail(at(key), "expected a string, got " + type_name(*v));
    const std::string name = v->get<std::string>();
    std::vector<std::string> names;
    for (Enum e : options) {
      if (name == to_string(e)) {
        out = e;
        return;
      }
      names.push_back(std::string("\"") + to_string(e) + "\"");
    }
    fail(at(key), "unknown value \"" + shown(name) + "\"; expected one of " + list(names));
  }

  void finish() const {
    for (auto it = j_.begin(); it != j_.end(); ++it) {
      if (std::find(known_.begin(), known_.end(), it.key()) != known_.end()) continue;
      std::string best;
      size_t best_distance = std::numeric_limits<size_t>::max();
      for (const std::string& k : known_) {
        const size_t d = edit_distance(it.key(), k);
        if (d < best_distance) best_distance = d, best = k;
      }
      std::string problem = "unknown key";
      if (!best.empty() && best_distance <= std::max<size_t>(2, best.size() / 3))
        problem += "; did you mean \"" + best + "\"?";
      else
        problem += "; known keys here: " + list(known_);
      fail(at(shown(it.key())), problem);
    }
  }

  static double as_number(const json& v, const std::string& path) {
    if (!v.is_number()) fail(path, "expected a number, got " + type_name(v));
    const double x = v.get<double>();
    if (!std::isfinite(x)) fail(path, "must be a finite number");
    return x;
  }
  static int as_integer(const json& v, const std::string& path) {
    const double x = as_number(v, path);
    if (x != std::floor(x)) fail(path, "expected an integer, got " + show(v));
    if (std::abs(x) > 1e9) fail(path, show(v) + " is too large (at most 1e9)");
    return static_cast<int>(x);
  }
  static Vec3 as_vec3(const json& v, const std::string& path) {
    if (!v.is_array() || v.size() != 3)
      fail(path, "expected an array of 3 numbers [x, y, z], got " + show(v));
    return {as_number(v[0], path + "[0]"), as_number(v[1], path + "[1]"),
            as_number(v[2], path + "[2]")};
  }
  static void pair(const json& v, const std::string& path, const char* form) {
    if (!v.is_array() || v.size() != 2)
      fail(path, std::string("expected an array of 2 ") + form + ", got " + show(v));
  }

 private:
  const json& j_;
  std::string path_;
  std::vector<std::string> known_;
};

void read_springs(Reader& springs, const std::string& kind, SpringParams& p) {
  if (const json* v = springs.find(kind)) {
    Reader r(*v, springs.at(kind));
    r.number("stiffness", p.stiffness);
    r.number("damping", p.damping);
    r.finish();
  }
}

// One pin: a corner name, [col, row], {"vertex": i} or {"box": {...}}.
MotionDef read_motion(const json& v, const std::string& path);

Pin read_pin(const json& p, const std::string& at) {
  if (p.is_string()) {
    const std::string name = p.get<std::string>();
    if (name == "top-left") return {0, 0};
    if (name == "top-right") return {-1, 0};
    if (name == "bottom-left") return {0, -1};
    if (name == "bottom-right") return {-1, -1};
    fail(at, "unknown corner \"" + shown(name) +
                 "\"; expected \"top-left\", \"top-right\", \"bottom-left\", "
                 "\"bottom-right\", a grid index [col, row], {\"vertex\": i}, {\"box\": "
                 "{\"min\": [x, y, z], \"max\": [x, y, z]}} or {\"ball\": {\"center\": "
                 "[x, y, z], \"radius\": r}}");
  }
  if (p.is_object() && p.contains("pin")) {
    // {"pin": <any pin form>, "motion": {...}}: the form's particles follow the motion.
    Reader r(p, at);
    const json& form = *r.find("pin");
    if (form.is_object() && form.contains("pin"))
      fail(at + ".pin", "holds another {\"pin\": ...}; give the pin's form itself there");
    Pin pin = read_pin(form, at + ".pin");
    if (const json* m = r.find("motion")) pin.motion = read_motion(*m, at + ".motion");
    r.finish();
    return pin;
  }
  if (p.is_object()) {
    Reader r(p, at);
    const json* vertex = r.find("vertex");
    const json* box = r.find("box");
    const json* ball = r.find("ball");
    if ((vertex != nullptr) + (box != nullptr) + (ball != nullptr) != 1)
      fail(at,
           "expected one of {\"vertex\": i}, {\"box\": {\"min\": [x, y, z], \"max\": "
           "[x, y, z]}} or {\"ball\": {\"center\": [x, y, z], \"radius\": r}}");
    Pin pin;
    if (vertex) {
      pin = Pin::at_vertex(Reader::as_integer(*vertex, at + ".vertex"));
    } else if (ball) {
      Reader b(*ball, at + ".ball");
      Vec3 center = Vec3::Zero();
      double radius = 0.0;
      if (!b.find("center")) fail(at + ".ball.center", "missing");
      if (!b.find("radius")) fail(at + ".ball.radius", "missing");
      b.vec3("center", center);
      b.number("radius", radius);
      b.finish();
      pin = Pin::in_ball(center, radius);
    } else {
      Reader b(*box, at + ".box");
      Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();
      if (!b.find("min")) fail(at + ".box.min", "missing");
      if (!b.find("max")) fail(at + ".box.max", "missing");
      b.vec3("min", lo);
      b.vec3("max", hi);
      b.finish();
      pin = Pin::in_box(lo, hi);
    }
    if (const json* m = r.find("motion")) pin.motion = read_motion(*m, at + ".motion");
    r.finish();
    return pin;
  }
  Reader::pair(p, at,
               "integers [col, row], a corner name, {\"vertex\": i}, {\"box\": ...} or "
               "{\"ball\": ...}");
  return {Reader::as_integer(p[0], at + "[0]"), Reader::as_integer(p[1], at + "[1]")};
}

// A number, or [warp, weft].
Vec2 read_warp_weft(const json& v, const std::string& path, const char* unit) {
  if (v.is_number()) {
    const double x = Reader::as_number(v, path);
    return Vec2(x, x);
  }
  Reader::pair(v, path,
               (std::string("numbers [warp, weft] in ") + unit + ", or one number").c_str());
  return Vec2(Reader::as_number(v[0], path + "[0]"), Reader::as_number(v[1], path + "[1]"));
}

std::string preset_list() {
  std::string out;
  for (const std::string& n : material_preset_names())
    out += (out.empty() ? "\"" : ", \"") + n + "\"";
  return out;
}

MaterialDef preset_named(const std::string& name, const std::string& path) {
  if (std::optional<MaterialDef> m = material_preset(name)) return *m;
  fail(path, "unknown material \"" + shown(name) + "\"; the presets are " + preset_list() +
                 ", or give an object with density, stretch, shear and bending");
}

}  // namespace

MaterialDef read_material(const json& v, const std::string& path) {
  if (v.is_string()) return preset_named(v.get<std::string>(), path);
  if (!v.is_object())
    fail(path,
         "expected a preset's name (" + preset_list() + ") or an object, got " + type_name(v));
  Reader r(v, path);
  MaterialDef m;
  const json* preset = r.find("preset");
  if (preset) {
    if (!preset->is_string())
      fail(r.at("preset"), "expected a preset's name, got " + type_name(*preset));
    m = preset_named(preset->get<std::string>(), r.at("preset"));
  } else {
    // Without a preset to start from, the four measured quantities have no default.
    for (const char* key : {"density", "stretch", "shear", "bending"})
      if (!v.contains(key))
        fail(r.at(key),
             "missing; a material without \"preset\" needs density (kg/m²), "
             "stretch (N/m), shear (N/m) and bending (N·m)");
    m.name.clear();
  }
  r.number("density", m.density);
  if (const json* s = r.find("stretch")) m.stretch = read_warp_weft(*s, r.at("stretch"), "N/m");
  r.number("shear", m.shear);
  if (const json* b = r.find("bending")) m.bending = read_warp_weft(*b, r.at("bending"), "N·m");
  r.number("compression", m.compression);
  r.number("damping", m.damping);
  r.finish();
  return m;
}

namespace {

// A part that is off, on with its defaults, or on with settings: false, true, or an object of
// settings, which `settings` reads.
template <typename ReadSettings>
void read_switch(const json& v, const std::string& path, bool& enabled, const char* expected,
                 ReadSettings&& settings) {
  if (v.is_boolean()) {
    enabled = v.get<bool>();
    return;
  }
  if (!v.is_object()) fail(path, std::string("expected ") + expected + ", got " + type_name(v));
  Reader r(v, path);
  enabled = true;
  settings(r);
  r.finish();
}

std::vector<Pin> read_pins(const json& v, const std::string& path) {
  if (!v.is_array()) fail(path, "expected an array of pins, got " + type_name(v));
  std::vector<Pin> pins;
  for (size_t k = 0; k < v.size(); ++k)
    pins.push_back(read_pin(v[k], path + "[" + std::to_string(k) + "]"));
  return pins;
}

// cloth.transform: {"translate": [x, y, z], "rotate": [rx, ry, rz], "scale": s or [sx, sy, sz]}.
MeshTransform read_transform(const json& v, const std::string& path) {
  Reader r(v, path);
  MeshTransform t;
  r.vec3("translate", t.translate);
  r.vec3("rotate", t.rotate);
  if (const json* s = r.find("scale")) {
    if (s->is_number()) {
      const double k = Reader::as_number(*s, path + ".scale");
      t.scale = Vec3(k, k, k);
    } else {
      t.scale = Reader::as_vec3(*s, path + ".scale");
    }
  }
  r.finish();
  return t;
}

// The mesh file named at cloth.mesh, found in `folder` when relative: read and kept whole in the
// definition, with the path it was found at (lexically normal) for messages and scene files.
// motion: {"keys": [{"t": s, "translate": [x, y, z], "rotate": [rx, ry, rz]}, ...],
// "loop": false, "pivot": [x, y, z]}.
MotionDef read_motion(const json& v, const std::string& path) {
  Reader r(v, path);
  MotionDef m;
  const json* keys = r.find("keys");
  if (!keys)
    fail(path + ".keys",
         "missing; expected an array of {\"t\": s, \"translate\": [x, y, z], "
         "\"rotate\": [rx, ry, rz]}");
  if (!keys->is_array() || keys->empty())
    fail(path + ".keys", "expected a non-empty array of keys, got " + type_name(*keys));
  for (size_t k = 0; k < keys->size(); ++k) {
    const std::string at = path + ".keys[" + std::to_string(k) + "]";
    Reader kr((*keys)[k], at);
    MotionKey key;
    if (!kr.find("t")) fail(at + ".t", "missing; expected the key's time in s");
    kr.number("t", key.t);
    kr.vec3("translate", key.translate);
    kr.vec3("rotate", key.rotate);
    kr.finish();
    m.keys.push_back(key);
  }
  if (const json* l = r.find("loop")) {
    if (!l->is_boolean()) fail(path + ".loop", "expected true or false, got " + type_name(*l));
    m.loop = l->get<bool>();
  }
  if (const json* p = r.find("pivot")) {
    m.has_pivot = true;
    m.pivot = Reader::as_vec3(*p, path + ".pivot");
  }
  r.finish();
  return m;
}

// An OBJ file named at `path`, found in `folder` when relative: the mesh and the path it was
// found at (lexically normal) for messages and scene files.
std::shared_ptr<const ClothMesh> read_mesh_file(const json& v, const std::string& path,
                                                const std::string& folder, std::string& found) {
  namespace fs = std::filesystem;
  if (!v.is_string()) fail(path, "expected the path of an OBJ file, got " + type_name(v));
  const std::string name = v.get<std::string>();
  if (name.empty()) fail(path, "is empty; expected the path of an OBJ file");
  fs::path file(name);
  if (file.is_relative() && !folder.empty()) file = fs::path(folder) / file;
  found = file.lexically_normal().string();
  try {
    return std::make_shared<const ClothMesh>(read_obj(found));
  } catch (const InputError& e) {
    fail(path + " (" + found + ")", e.problem());
  }
}

// The mesh file named at cloth.mesh, kept whole in the definition.
void read_mesh(const json& v, const std::string& folder, ClothDef& c) {
  c.mesh = read_mesh_file(v, "cloth.mesh", folder, c.mesh_file);
}

ColliderDef read_collider(const json& v, const std::string& path, const std::string& folder) {
  Reader r(v, path);
  ColliderDef c;
  const json* type = r.find("type");
  if (!type)
    fail(r.at("type"), "missing; expected \"sphere\", \"plane\", \"capsule\", \"box\" or \"mesh\"");
  if (type->is_string()) {
    // An unknown type: name the nearest (the key after it would be unknown anyway).
    const std::string name = type->get<std::string>();
    const ColliderType all[] = {ColliderType::sphere, ColliderType::plane, ColliderType::capsule,
                                ColliderType::box, ColliderType::mesh};
    bool known = false;
    std::string best, names;
    size_t best_distance = std::numeric_limits<size_t>::max();
    for (ColliderType t : all) {
      known = known || name == to_string(t);
      const size_t d = edit_distance(name, to_string(t));
      if (d < best_distance) best_distance = d, best = to_string(t);
      names += std::string(names.empty() ? "" : ", ") + "\"" + to_string(t) + "\"";
    }
    if (!known)
      fail(r.at("type"), "unknown value \"" + shown(name) + "\"" +
                             (best_distance <= std::max<size_t>(2, best.size() / 3)
                                  ? "; did you mean \"" + best + "\"?"
                                  : "") +
                             " Expected one of " + names);
  }
  r.choice("type", c.type,
           {ColliderType::sphere, ColliderType::plane, ColliderType::capsule, ColliderType::box,
            ColliderType::mesh});
  switch (c.type) {
    case ColliderType::sphere:
      r.vec3("center", c.center);
      r.number("radius", c.radius);
      break;
    case ColliderType::plane:
      c.center = Vec3::Zero();
      r.vec3("point", c.center);
      r.vec3("normal", c.normal);
      break;
    case ColliderType::capsule:
      r.vec3("a", c.a);
      r.vec3("b", c.b);
      r.number("radius", c.radius);
      break;
    case ColliderType::box:
      r.vec3("center", c.center);
      r.vec3("half_extents", c.half_extents);
      r.vec3("rotate", c.rotate);
      break;
    case ColliderType::mesh: {
      const json* file = r.find("file");
      if (!file) fail(r.at("file"), "missing; expected the path of an OBJ file");
      c.mesh = read_mesh_file(*file, r.at("file"), folder, c.mesh_file);
      if (const json* t = r.find("transform")) c.transform = read_transform(*t, r.at("transform"));
      break;
    }
  }
  r.number("friction", c.friction);
  r.number("thickness", c.thickness);
  if (const json* m = r.find("motion")) c.motion = read_motion(*m, r.at("motion"));
  r.finish();
  return c;
}

// A scene is a few kilobytes; this leaves room for any cloth with every particle pinned by
// index, and bounds what a mistaken file (a log, a disk image, /dev/zero) can cost to read.
constexpr size_t kMaxSceneBytes = size_t{16} << 20;

[[noreturn]] void too_large() {
  fail("", "is larger than the 16 MiB a scene file may be");
}

// The file's bytes: a regular file, a pipe (`<(...)`), a device, or standard input for `-`.
std::string read_text(const std::string& file) {
  namespace fs = std::filesystem;
  FILE* in = stdin;
  if (file != "-") {
    std::error_code ec;
    const fs::file_status status = fs::status(file, ec);
    if (!fs::exists(status)) fail("", "no such file");
    if (fs::is_directory(status)) fail("", "is a folder, not a scene file");
    if (fs::is_regular_file(status) && fs::file_size(file, ec) > kMaxSceneBytes) too_large();
    in = std::fopen(file.c_str(), "rb");
    if (!in) fail("", std::string("cannot be opened for reading: ") + std::strerror(errno));
  }
  std::string text;
  char buf[1 << 16];
  bool large = false;
  for (size_t n; !large && (n = std::fread(buf, 1, sizeof buf, in)) > 0;) {
    large = text.size() + n > kMaxSceneBytes;
    if (!large) text.append(buf, n);
  }
  const bool bad = std::ferror(in);
  if (in != stdin) std::fclose(in);
  if (large) too_large();
  if (bad) fail("", "cannot be read");
  if (text.find_first_not_of(" \t\r\n") == std::string::npos) fail("", "the file is empty");
  return text;
}

// nlohmann's message without its "[json.exception.name.id] " prefix.
const char* without_prefix(const nlohmann::json::exception& e) {
  const char* msg = e.what();
  const char* end = std::strchr(msg, ']');
  return end && end[1] == ' ' ? end + 2 : msg;
}

json parse_json(const std::string& text) {
  try {
    return json::parse(text);
  } catch (const json::exception& e) {
    // "[json.exception.parse_error.101] parse error at line 3, column 5: ...", or
    // "[json.exception.out_of_range.406] number overflow parsing '1e999'".
    fail("", std::string("invalid JSON: ") + without_prefix(e));
  }
}

// Paths as InputError writes them: colliders.0.radius -> colliders[0].radius.
std::string display_path(const std::vector<std::string>& parts) {
  std::string out;
  for (const std::string& p : parts) {
    const bool index = !p.empty() && std::all_of(p.begin(), p.end(), ::isdigit);
    out += index ? "[" + p + "]" : (out.empty() ? "" : ".") + p;
  }
  return out;
}

}  // namespace

SceneDef parse_scene(const json& j, const std::string& source, const std::string& folder) {
  try {
    SceneDef def;
    Reader top(j, "");
    top.string("name", def.name);
    if (const json* cj = top.find("cloth")) {
      ClothDef& c = def.cloth;
      Reader r(*cj, "cloth");
      if (const json* v = r.find("mesh")) {
        // A mesh replaces the grid: the grid's keys beside it are a mistake worth naming.
        std::string grid_keys;
        for (const char* key : {"size", "resolution", "origin", "orientation"})
          if (cj->contains(key))
            grid_keys += std::string(grid_keys.empty() ? "" : ", ") + "cloth." + key;
        if (!grid_keys.empty())
          fail("cloth.mesh", "is given, so the grid's keys (" + grid_keys +
                                 ") have no meaning beside it; remove them and place the mesh "
                                 "with cloth.transform");
        read_mesh(*v, folder, c);
      }
      if (const json* v = r.find("transform")) {
        if (!c.mesh) fail("cloth.transform", "places a mesh; there is no cloth.mesh");
        c.transform = read_transform(*v, "cloth.transform");
      }
      if (const json* v = r.find("size")) {
        Reader::pair(*v, "cloth.size", "numbers [width, height] in m");
        c.width = Reader::as_number((*v)[0], "cloth.size[0]");
        c.height = Reader::as_number((*v)[1], "cloth.size[1]");
      }
      if (const json* v = r.find("resolution")) {
        Reader::pair(*v, "cloth.resolution", "integers [columns, rows]");
        c.cols = Reader::as_integer((*v)[0], "cloth.resolution[0]");
        c.rows = Reader::as_integer((*v)[1], "cloth.resolution[1]");
      }
      r.vec3("origin", c.origin);
      r.choice("orientation", c.orientation, {Orientation::vertical, Orientation::horizontal});
      r.number("mass", c.mass);
      if (const json* v = r.find("material")) {
        // The material sets the masses and the springs' stiffness: either beside it says two
        // different things.
        for (const char* key : {"mass", "springs"})
          if (cj->contains(key))
            fail("cloth.material",
                 std::string("and cloth.") + key +
                     " are both given; a material derives the "
                     "masses and the springs' stiffness and damping itself: remove cloth." +
                     key);
        c.material = read_material(*v, "cloth.material");
      }
      if (const json* v = r.find("pins"))
        c.pins = read_pins(*v, "cloth.pins");
      else if (c.mesh)
        c.pins.clear();  // the default corners are a grid's; a mesh has none
      if (const json* v = r.find("springs")) {
        Reader s(*v, "cloth.springs");
        read_springs(s, "structural", c.structural);
        read_springs(s, "shear", c.shear);
        read_springs(s, "bending", c.bending);
        s.finish();
      }
      r.number("perturbation", c.perturbation);
      if (const json* v = r.find("long_range"))
        read_switch(*v, "cloth.long_range", c.long_range.enabled, "false, true or {\"slack\": s}",
                    [&](Reader& lr) { lr.number("slack", c.long_range.slack); });
      if (const json* v = r.find("self_collision"))
        read_switch(*v, "cloth.self_collision", c.self_collision.enabled,
                    "false, true or {\"thickness\": m, \"friction\": mu}", [&](Reader& sc) {
                      sc.number("thickness", c.self_collision.thickness);
                      sc.number("friction", c.self_collision.friction);
                    });
      r.finish();
    }
    if (const json* fj = top.find("forces")) {
      Reader r(*fj, "forces");
      r.vec3("gravity", def.forces.gravity);
      r.number("air_drag", def.forces.air_drag);
      r.number("air_density", def.forces.air_density);
      r.number("drag_coefficient", def.forces.drag_coefficient);
      if (const json* wj = r.find("wind")) {
        WindDef& w = def.forces.wind;
        Reader wr(*wj, "forces.wind");
        wr.choice("model", w.model, {WindModel::seed, WindModel::aero});
        wr.vec3("direction", w.direction);
        wr.number("strength", w.strength);
        wr.number("coefficient", w.coefficient);
        wr.number("density", w.density);
        wr.number("gust", w.gust);
        wr.number("gust_frequency", w.gust_frequency);
        wr.finish();
      }
      r.finish();
    }
    if (const json* cj = top.find("colliders")) {
      if (!cj->is_array()) fail("colliders", "expected an array, got " + type_name(*cj));
      for (size_t k = 0; k < cj->size(); ++k)
        def.colliders.push_back(
            read_collider((*cj)[k], "colliders[" + std::to_string(k) + "]", folder));
    }
    if (const json* sj = top.find("solver")) {
      Reader r(*sj, "solver");
      r.choice("method", def.solver.method,
               std::vector<Method>(std::begin(kAllMethods), std::end(kAllMethods)));
      r.choice("precision", def.solver.precision, {Precision::f64, Precision::f32});
      r.number("dt", def.solver.dt);
      r.integer("substeps", def.solver.substeps);
      r.number("safety", def.solver.safety);
      r.integer("max_substeps", def.solver.max_substeps);
      r.integer("iterations", def.solver.iterations);
      r.integer("stiff_sweeps", def.solver.stiff_sweeps);
      r.integer("line_passes", def.solver.line_passes);
      r.number("line_relaxation", def.solver.line_relaxation);
      r.number("cg_tolerance", def.solver.cg_tolerance);
      r.integer("cg_max_iterations", def.solver.cg_max_iterations);
      r.number("chebyshev_rho", def.solver.chebyshev_rho);
      r.number("tolerance", def.solver.tolerance);
      r.finish();
    }
    top.number("duration", def.duration);
    top.finish();
    check(def);
    return def;
  } catch (const InputError& e) {
    throw InputError(e.path().empty() ? source : source + ": " + e.path(), e.problem());
  }
}

void apply_override(json& scene, const std::string& assignment) {
  const size_t eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    fail("--set " + shown(assignment), "expected KEY=VALUE, e.g. cloth.resolution=[64,64]");
  const std::string key = shown(assignment.substr(0, eq));
  const std::string text = assignment.substr(eq + 1);
  json value;
  try {
    value = json::parse(text);
  } catch (const json::parse_error&) {
    value = text;  // a bare word is a string
  } catch (const json::exception& e) {
    fail("--set " + key, without_prefix(e));
  }
  std::vector<std::string> parts;
  std::stringstream ss(assignment.substr(0, eq));
  for (std::string part; std::getline(ss, part, '.');) {
    if (part.empty()) fail("--set " + key, "empty component in the key");
    parts.push_back(part);
  }
  json* node = &scene;
  for (size_t k = 0; k < parts.size(); ++k) {
    const std::string& p = parts[k];
    const bool last = k + 1 == parts.size();
    if (node->is_array()) {
      const bool index = std::all_of(p.begin(), p.end(), ::isdigit) && p.size() < 9;
      const std::string where = display_path({parts.begin(), parts.begin() + k});
      if (!index)
        fail("--set " + key, where + " is an array; expected an index, got \"" + shown(p) + "\"");
      const size_t i = std::stoul(p);
      if (i >= node->size())
        fail("--set " + key, where + " has " + std::to_string(node->size()) +
                                 " element(s); there is no element " + p);
      node = &(*node)[i];
    } else {
      if (node->is_null()) *node = json::object();
      if (!node->is_object())
        fail("--set " + key, display_path({parts.begin(), parts.begin() + k}) +
                                 " is not an object, so it has no key \"" + shown(p) + "\"");
      node = &(*node)[p];
    }
    if (last) *node = value;
  }
}

std::string source_name(const std::string& file) {
  return file == "-" ? "standard input" : file;
}

json load_scene_json(const std::string& file, const std::vector<std::string>& overrides) {
  try {
    json j = parse_json(read_text(file));
    for (const std::string& o : overrides) apply_override(j, o);
    return j;
  } catch (const InputError& e) {
    const std::string source = source_name(file);
    throw InputError(e.path().empty() ? source : source + ": " + e.path(), e.problem());
  }
}

std::string scene_folder(const std::string& file) {
  return file == "-" ? "" : std::filesystem::path(file).parent_path().string();
}

SceneDef load_scene(const std::string& file, const std::vector<std::string>& overrides) {
  return parse_scene(load_scene_json(file, overrides), source_name(file), scene_folder(file));
}

json material_json(const MaterialDef& m) {
  json out = {{"density", m.density},
              {"stretch", {m.stretch.x(), m.stretch.y()}},
              {"shear", m.shear},
              {"bending", {m.bending.x(), m.bending.y()}},
              {"compression", m.compression},
              {"damping", m.damping}};
  if (!m.name.empty()) out["preset"] = m.name;
  return out;
}

json to_json(const SceneDef& d) {
  auto v3 = [](const Vec3& v) { return json::array({v.x(), v.y(), v.z()}); };
  auto springs = [](const SpringParams& p) {
    return json{{"stiffness", p.stiffness}, {"damping", p.damping}};
  };
  auto motion = [&](const MotionDef& m) {
    json keys = json::array();
    for (const MotionKey& k : m.keys)
      keys.push_back({{"t", k.t}, {"translate", v3(k.translate)}, {"rotate", v3(k.rotate)}});
    json o{{"keys", keys}, {"loop", m.loop}};
    if (m.has_pivot) o["pivot"] = v3(m.pivot);
    return o;
  };
  json pins = json::array();
  for (const Pin& p : d.cloth.pins) {
    json pin;
    switch (p.kind) {
      case PinKind::grid:
        pin = json::array({p.col, p.row});
        break;
      case PinKind::vertex:
        pin = json{{"vertex", p.vertex}};
        break;
      case PinKind::box:
        pin = json{{"box", json{{"min", v3(p.box_min)}, {"max", v3(p.box_max)}}}};
        break;
      case PinKind::ball:
        pin = json{{"ball", json{{"center", v3(p.ball_center)}, {"radius", p.ball_radius}}}};
        break;
    }
    // A moving pin in the {"pin": form, "motion": ...} form, which holds any form.
    if (p.motion.moves()) pin = json{{"pin", pin}, {"motion", motion(p.motion)}};
    pins.push_back(pin);
  }
  json colliders = json::array();
  for (const ColliderDef& c : d.colliders) {
    json o{{"type", to_string(c.type)}, {"friction", c.friction}, {"thickness", c.thickness}};
    switch (c.type) {
      case ColliderType::sphere:
        o["center"] = v3(c.center);
        o["radius"] = c.radius;
        break;
      case ColliderType::plane:
        o["point"] = v3(c.center);
        o["normal"] = v3(c.normal);
        break;
      case ColliderType::capsule:
        o["a"] = v3(c.a);
        o["b"] = v3(c.b);
        o["radius"] = c.radius;
        break;
      case ColliderType::box:
        o["center"] = v3(c.center);
        o["half_extents"] = v3(c.half_extents);
        o["rotate"] = v3(c.rotate);
        break;
      case ColliderType::mesh:
        o["file"] = c.mesh_file;
        o["transform"] = {{"translate", v3(c.transform.translate)},
                          {"rotate", v3(c.transform.rotate)},
                          {"scale", v3(c.transform.scale)}};
        break;
    }
    if (c.motion.moves()) o["motion"] = motion(c.motion);
    colliders.push_back(o);
  }
  const ClothDef& c = d.cloth;
  const WindDef& w = d.forces.wind;
  json cloth{
      {"pins", pins},
      {"perturbation", c.perturbation},
      {"long_range", c.long_range.enabled ? json{{"slack", c.long_range.slack}} : json(false)},
      {"self_collision", c.self_collision.enabled ? json{{"thickness", c.self_collision.thickness},
                                                         {"friction", c.self_collision.friction}}
                                                  : json(false)}};
  if (c.material) {
    cloth["material"] = material_json(*c.material);
  } else {
    cloth["mass"] = c.mass;
    cloth["springs"] = {{"structural", springs(c.structural)},
                        {"shear", springs(c.shear)},
                        {"bending", springs(c.bending)}};
  }
  if (c.mesh) {
    cloth["mesh"] = c.mesh_file;
    cloth["transform"] = {{"translate", v3(c.transform.translate)},
                          {"rotate", v3(c.transform.rotate)},
                          {"scale", v3(c.transform.scale)}};
  } else {
    cloth["size"] = {c.width, c.height};
    cloth["resolution"] = {c.cols, c.rows};
    cloth["origin"] = v3(c.origin);
    cloth["orientation"] = to_string(c.orientation);
  }
  return json{{"name", d.name},
              {"cloth", cloth},
              {"forces",
               {{"gravity", v3(d.forces.gravity)},
                {"air_drag", d.forces.air_drag_for(d.cloth.material.has_value())},
                {"air_density", d.forces.air_density_for(d.cloth.material.has_value())},
                {"drag_coefficient", d.forces.drag_coefficient},
                {"wind",
                 {{"model", to_string(w.model)},
                  {"direction", v3(w.direction)},
                  {"strength", w.strength},
                  {"coefficient", w.coefficient},
                  {"density", w.density},
                  {"gust", w.gust},
                  {"gust_frequency", w.gust_frequency}}}}},
              {"colliders", colliders},
              {"solver",
               {{"method", to_string(d.solver.method)},
                {"precision", to_string(d.solver.precision)},
                {"dt", d.solver.dt},
                {"substeps", d.solver.substeps},
                {"safety", d.solver.safety},
                {"max_substeps", d.solver.max_substeps},
                {"iterations", d.solver.iterations},
                {"stiff_sweeps", d.solver.stiff_sweeps},
                {"line_passes", d.solver.line_passes},
                {"line_relaxation", d.solver.line_relaxation},
                {"cg_tolerance", d.solver.cg_tolerance},
                {"cg_max_iterations", d.solver.cg_max_iterations},
                {"chebyshev_rho", d.solver.chebyshev_rho},
                {"tolerance", d.solver.tolerance}}},
              {"duration", d.duration}};
}

}  // namespace drape::io
