// Scene files: JSON in, SceneDef out, every problem reported with the file, the JSON path and
// what is wrong. The keys, their units, defaults and ranges are listed in the README.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "drape/scene.h"

namespace drape::io {

/// Reads `file`, applies the overrides ("cloth.resolution=[64,64]": a dotted path, then a JSON
/// value; a bare word is a string), checks types, names and ranges, and returns the scene.
/// `file` may be a regular file, a pipe or a device, or `-` for standard input; one of more than
/// 16 MiB is refused. Throws InputError whose message starts with the file name.
SceneDef load_scene(const std::string& file, const std::vector<std::string>& overrides = {});

/// The first half of load_scene: the file's JSON with the overrides applied, not yet checked,
/// for a caller that sets more keys before parse_scene (drape compare sets each method).
nlohmann::json load_scene_json(const std::string& file,
                               const std::vector<std::string>& overrides = {});

/// How messages name a scene file: the file, or "standard input" for `-`.
std::string source_name(const std::string& file);

/// The folder a scene file's relative paths (cloth.mesh) are found in: the file's own, or the
/// working directory for standard input.
std::string scene_folder(const std::string& file);

/// The same as load_scene for JSON already in memory; `source` names it in messages, and a
/// relative `cloth.mesh` is found in `folder` (empty: the working directory).
SceneDef parse_scene(const nlohmann::json& j, const std::string& source,
                     const std::string& folder = "");

/// Sets one "dotted.path=value" override in a scene's JSON. Objects on the way are created;
/// array elements are addressed by number (colliders.0.radius). Throws InputError.
void apply_override(nlohmann::json& scene, const std::string& assignment);

/// A material as cloth.material holds it: a preset's name, or an object of density, stretch,
/// shear, bending, compression and damping (starting from {"preset": name} when it has one).
/// Throws InputError at `path`.
MaterialDef read_material(const nlohmann::json& v, const std::string& path);

/// The object read_material reads back as `m`.
nlohmann::json material_json(const MaterialDef& m);

/// Every key of a scene, with every value given: parse_scene(to_json(d)) reproduces d.
nlohmann::json to_json(const SceneDef& def);

}  // namespace drape::io
