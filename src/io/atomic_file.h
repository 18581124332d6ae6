// Files that appear whole or not at all: written under a temporary name, renamed on commit.
#pragma once

#include <cstdio>
#include <string>

namespace drape::io {

/// A FILE* that writes to FILE.tmp and renames it over FILE on commit(). Destroyed without a
/// commit (an exception on the way), it removes the temporary file, so a reader never sees half
/// a file under the real name.
class AtomicFile {
 public:
  explicit AtomicFile(std::string file);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  FILE* get() { return f_; }
  const std::string& file() const { return file_; }
  const std::string& temporary() const { return tmp_; }
  /// Closes the temporary file and renames it. Throws std::runtime_error naming the file if
  /// anything written so far failed.
  void commit();

 private:
  std::string file_, tmp_;
  FILE* f_ = nullptr;
};

/// Writes `text` to `file` through a temporary name and a rename.
void write_file_atomically(const std::string& file, const std::string& text);

/// Throws std::runtime_error naming `file` unless all of [data, data + bytes) was written.
void write_all(FILE* f, const void* data, size_t bytes, const std::string& file);

}  // namespace drape::io
