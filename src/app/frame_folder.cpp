#include "app/frame_folder.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "drape/error.h"
#include "io/output_file.h"

namespace drape::app {

namespace fs = std::filesystem;

std::string frame_file(const std::string& folder, int64_t frame, const std::string& extension) {
  char name[64];
  std::snprintf(name, sizeof name, "frame_%05lld.%s", static_cast<long long>(frame),
                extension.c_str());
  return (fs::path(folder) / name).string();
}

bool is_frame_file(const std::string& name, const std::vector<std::string>& extensions) {
  const std::string prefix = "frame_";
  const size_t dot = name.rfind('.');
  if (name.rfind(prefix, 0) != 0 || dot == std::string::npos || dot < prefix.size() + 5)
    return false;
  const bool digits = std::all_of(name.begin() + prefix.size(), name.begin() + dot,
                                  [](char c) { return c >= '0' && c <= '9'; });
  return digits &&
         std::find(extensions.begin(), extensions.end(), name.substr(dot + 1)) != extensions.end();
}

namespace {

// The frames in `folder` (none when it does not exist).
std::vector<fs::path> frames_in(const std::string& folder,
                                const std::vector<std::string>& extensions) {
  std::vector<fs::path> frames;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(folder, ec)) {
    std::error_code type_ec;
    if (entry.is_regular_file(type_ec) && !entry.is_symlink(type_ec) &&
        is_frame_file(entry.path().filename().string(), extensions))
      frames.push_back(entry.path());
  }
  return frames;
}

}  // namespace

void check_frame_folder(const std::string& option, const std::string& folder,
                        const std::vector<std::string>& extensions, bool force) {
  io::check_output_folder(option, folder);
  if (!force && !frames_in(folder, extensions).empty())
    throw InputError(option + " " + folder,
                     "already holds frames of an earlier run; choose another folder or pass "
                     "--force to replace them");
}

int64_t prepare_frame_folder(const std::string& option, const std::string& folder,
                             const std::vector<std::string>& extensions) {
  std::error_code ec;
  fs::create_directories(folder, ec);
  if (ec) throw InputError(option + " " + folder, "cannot create the folder: " + ec.message());
  int64_t removed = 0;
  for (const fs::path& frame : frames_in(folder, extensions)) {
    removed += fs::remove(frame, ec);
    if (ec)
      throw InputError(option + " " + folder, "cannot remove the earlier run's " +
                                                  frame.filename().string() + ": " + ec.message());
  }
  return removed;
}

}  // namespace drape::app
