#include "io/atomic_file.h"

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace drape::io {

AtomicFile::AtomicFile(std::string file) : file_(std::move(file)), tmp_(file_ + ".tmp") {
  f_ = std::fopen(tmp_.c_str(), "wb");
  if (!f_) throw std::runtime_error(file_ + ": cannot write: " + std::strerror(errno));
}

AtomicFile::~AtomicFile() {
  if (f_) {
    std::fclose(f_);
    std::remove(tmp_.c_str());
  }
}

void AtomicFile::commit() {
  const bool ok = !std::ferror(f_);
  const bool closed = std::fclose(f_) == 0;
  f_ = nullptr;
  if (!ok || !closed || std::rename(tmp_.c_str(), file_.c_str()) != 0) {
    const int error = errno;
    std::remove(tmp_.c_str());
    throw std::runtime_error(file_ + ": cannot write: " + std::strerror(error));
  }
}

void write_file_atomically(const std::string& file, const std::string& text) {
  AtomicFile out(file);
  write_all(out.get(), text.data(), text.size(), file);
  out.commit();
}

void write_all(FILE* f, const void* data, size_t bytes, const std::string& file) {
  if (bytes > 0 && std::fwrite(data, 1, bytes, f) != bytes)
    throw std::runtime_error(file + ": cannot write: " + std::strerror(errno));
}

}  // namespace drape::io
