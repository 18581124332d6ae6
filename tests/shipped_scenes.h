// The shipped scenes' names (every scenes/*.json), so that each test that covers them all takes
// a new scene without being told.
#pragma once

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

namespace drape::testing_support {

inline std::vector<std::string> shipped_scene_names() {
  std::vector<std::string> names;
  for (const auto& entry :
       std::filesystem::directory_iterator(std::string(DRAPE_SOURCE_DIR) + "/scenes"))
    if (entry.path().extension() == ".json") names.push_back(entry.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace drape::testing_support
