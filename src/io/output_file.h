// Every file drape writes at a path the user gave it: stats, meshes, bench tables, pictures,
// screenshots, reports. What is at the path decides how it is written, so that a reader never
// sees half a file and nothing but the file's contents is ever replaced:
//  - `-` is standard output;
//  - a symbolic link is followed (through any number of links, up to 40), and its target is
//    written as below; the link stays;
//  - a named pipe, a device or a socket is opened and written to directly (a rename would
//    replace the special file with a regular one); opening a pipe waits for its reader;
//  - a regular file, or nothing, is written under a temporary name in the same folder and renamed
//    over the path when complete, keeping the permissions of a file it replaces;
//  - a folder is refused.
#pragma once

#include <signal.h>

#include <cstdio>
#include <stdexcept>
#include <string>

namespace drape::io {

/// An output that could not be written; the message starts with the file's name.
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Throws InputError (path "OPTION FILE") when `file` could not be written: a folder, a folder on
/// the way that does not exist or cannot be written in, a read-only file, a loop of links. Checks
/// by creating and removing a temporary file beside the target; leaves nothing behind.
void check_output(const std::string& option, const std::string& file);

/// The same for a folder drape fills with files (exports, renders): an existing folder must be
/// writable; a missing one must be creatable, its nearest existing parent a writable folder.
/// `-` and the empty path are refused.
void check_output_folder(const std::string& option, const std::string& folder);

/// One output being written. Nothing appears at the path until commit(); destroyed without a
/// commit, the temporary file is removed.
class OutputFile {
 public:
  /// Opens the file or its temporary. Throws OutputError naming `file` when it cannot.
  explicit OutputFile(const std::string& file);
  ~OutputFile();
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  FILE* get() const { return f_; }
  /// The path as the user gave it, for messages.
  const std::string& file() const { return file_; }
  /// Flushes, closes and renames into place. Throws OutputError when any write failed.
  void commit();

 private:
  [[noreturn]] void fail(int error);
  void discard();

  std::string file_;    // as the user gave it, for messages
  std::string target_;  // where the bytes go: the file, or a link's final target
  std::string tmp_;     // the temporary beside the target; empty when writing directly
  FILE* f_ = nullptr;
  mode_t mode_ = 0;      // permissions the renamed file gets
  bool stdout_ = false;  // `-`
  // A direct write to a pipe whose reader has gone must fail, not kill drape with SIGPIPE.
  bool pipe_ignored_ = false;
  struct sigaction old_pipe_ {};
};

/// Writes all of [data, data + bytes) to f. Throws OutputError naming `file` when it cannot.
void write_all(FILE* f, const void* data, size_t bytes, const std::string& file);

/// Writes `bytes` to `file` as above. Throws OutputError.
void write_output(const std::string& file, const std::string& bytes);

/// `text` made into one file-name component, for names drape builds from a scene's `name`:
/// every character but ASCII letters, digits, `.`, `_`, `-` and `+` becomes `_`, a leading `.`
/// too (so it is never `.`, `..` or hidden), at most 64 characters; empty text gives "untitled".
std::string file_name_from(const std::string& text);

}  // namespace drape::io
