// PC2 point caches: every frame's positions of one mesh in one file, the layout that Blender's
// Mesh Cache modifier, Houdini and 3ds Max play back on a mesh with the same vertex order.
//
// Little-endian: a 32-byte header (char[12] "POINTCACHE2\0", int32 version 1, int32 vertex
// count, float start frame, float sampling, int32 frame count), then frames × vertices ×
// float[3].
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "drape/math.h"
#include "io/output_file.h"

namespace drape::io {

inline constexpr size_t kPc2HeaderBytes = 32;

class Pc2Writer {
 public:
  /// Starts the cache `file` of `vertices` points, whose first frame is `start_frame` and whose
  /// frames lie `sampling` frames apart. It is written as io::OutputFile writes (under a
  /// temporary name beside it) until finish(); not to a pipe or a device, since its header is
  /// rewritten after every frame.
  Pc2Writer(std::string file, int32_t vertices, float start_frame, float sampling);

  /// Appends one frame (m; stored as float). The header's frame count is rewritten after each
  /// frame, so even the temporary file of a run killed outright is a valid cache of the frames
  /// written so far. Throws OutputError naming the file if it cannot be written.
  void add_frame(const std::vector<Vec3>& x);

  /// Renames the cache to its name: a reader never sees a cache whose header promises frames
  /// that are not there.
  void finish();

  int32_t frames() const { return frames_; }

 private:
  OutputFile out_;
  int32_t vertices_;
  int32_t frames_ = 0;
  std::vector<float> row_;  // one frame as floats, reused
};

}  // namespace drape::io
