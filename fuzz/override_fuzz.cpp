// Fuzzes the --set parser: each input line is one KEY=VALUE override applied to a full scene;
// the result is a scene or an InputError, never a crash.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "drape/error.h"
#include "io/scene_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const nlohmann::json base = [] {
    drape::SceneDef def;
    def.colliders.push_back({});
    return drape::io::to_json(def);
  }();
  nlohmann::json scene = base;
  std::istringstream lines(std::string(reinterpret_cast<const char*>(data), size));
  try {
    for (std::string line; std::getline(lines, line);) drape::io::apply_override(scene, line);
    (void)drape::io::parse_scene(scene, "fuzz.json");
  } catch (const drape::InputError&) {
  }
  return 0;
}
