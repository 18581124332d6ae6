#include "io/pc2_writer.h"

#include <bit>
#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace drape::io {

static_assert(std::endian::native == std::endian::little, "PC2 writer assumes little endian");

namespace {

// Byte offset of the header's frame count.
constexpr long kFrameCountOffset = 28;

void seek(FILE* f, long offset, int whence, const std::string& file) {
  if (std::fseek(f, offset, whence) != 0)
    throw OutputError(file + ": cannot write a PC2 cache here (" + std::strerror(errno) +
                      "): its header is rewritten after every frame, which a pipe or a device "
                      "cannot take");
}

}  // namespace

Pc2Writer::Pc2Writer(std::string file, int32_t vertices, float start_frame, float sampling)
    : out_(std::move(file)), vertices_(vertices), row_(3 * static_cast<size_t>(vertices)) {
  char header[kPc2HeaderBytes] = "POINTCACHE2";  // with its terminating zero: 12 bytes
  const int32_t version = 1, count = 0;
  std::memcpy(header + 12, &version, 4);
  std::memcpy(header + 16, &vertices_, 4);
  std::memcpy(header + 20, &start_frame, 4);
  std::memcpy(header + 24, &sampling, 4);
  std::memcpy(header + 28, &count, 4);
  write_all(out_.get(), header, sizeof header, out_.file());
}

void Pc2Writer::add_frame(const std::vector<Vec3>& x) {
  if (static_cast<int32_t>(x.size()) != vertices_)
    throw std::logic_error(out_.file() + ": a frame of " + std::to_string(x.size()) +
                           " points in a cache of " + std::to_string(vertices_));
  for (size_t i = 0; i < x.size(); ++i)
    for (int k = 0; k < 3; ++k) row_[3 * i + k] = static_cast<float>(x[i][k]);
  FILE* f = out_.get();
  write_all(f, row_.data(), row_.size() * sizeof(float), out_.file());
  ++frames_;
  // The frame's data goes out before the count that announces it (fseek flushes in order).
  seek(f, kFrameCountOffset, SEEK_SET, out_.file());
  write_all(f, &frames_, sizeof frames_, out_.file());
  seek(f, 0, SEEK_END, out_.file());
}

void Pc2Writer::finish() {
  out_.commit();
}

}  // namespace drape::io
