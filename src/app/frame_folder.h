// A folder of numbered frames, as `drape run --export` and `drape render` write them:
// frame_NNNNN.EXT (five digits or more), one file per frame kept. Runs never mix in one: a folder
// holding an earlier run's frames is refused, or with --force emptied of them (of them only).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace drape::app {

/// The file of frame `frame` in `folder`: frame_00012.obj.
std::string frame_file(const std::string& folder, int64_t frame, const std::string& extension);

/// Whether `name` is the name frame_file gives, with one of `extensions`.
bool is_frame_file(const std::string& name, const std::vector<std::string>& extensions);

/// Checks, changing nothing, that frames can be written into `folder` (see
/// io::check_output_folder) and, unless `force`, that it holds no frames with any of
/// `extensions`. Throws InputError (path "OPTION FOLDER").
void check_frame_folder(const std::string& option, const std::string& folder,
                        const std::vector<std::string>& extensions, bool force);

/// Creates `folder`, and removes the frames it holds with any of `extensions`: regular files
/// named as frame_file names them, nothing else (not a link, a folder, or any other file).
/// Throws InputError when it cannot. Returns the number of frames removed.
int64_t prepare_frame_folder(const std::string& option, const std::string& folder,
                             const std::vector<std::string>& extensions);

}  // namespace drape::app
