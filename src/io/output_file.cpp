#include "io/output_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <vector>

#include "drape/error.h"

namespace drape::io {

namespace fs = std::filesystem;

namespace {

enum class Kind { absent, regular, special, folder, standard_output };

struct Target {
  std::string path;  // links followed
  Kind kind = Kind::absent;
  mode_t mode = 0;  // permissions of what is there
};

// Linux follows at most 40 links in one path (MAXSYMLINKS); so does drape.
constexpr int kMaxLinks = 40;

// What is at `file`, with links followed. Returns the problem, or "" when there is none.
std::string resolve(const std::string& file, Target& t) {
  if (file == "-") {
    t = {file, Kind::standard_output, 0};
    return "";
  }
  if (file.empty()) return "the path is empty";
  std::string path = file;
  for (int links = 0;; ++links) {
    struct stat st;
    if (lstat(path.c_str(), &st) != 0) {
      if (errno != ENOENT) return std::strerror(errno);
      t = {path, Kind::absent, 0};
      return "";
    }
    if (S_ISLNK(st.st_mode)) {
      if (links == kMaxLinks) return "too many levels of symbolic links";
      std::error_code ec;
      const fs::path to = fs::read_symlink(path, ec);
      if (ec) return ec.message();
      path = to.is_absolute() ? to.string() : (fs::path(path).parent_path() / to).string();
      continue;
    }
    const Kind kind = S_ISDIR(st.st_mode)   ? Kind::folder
                      : S_ISREG(st.st_mode) ? Kind::regular
                                            : Kind::special;
    t = {path, kind, static_cast<mode_t>(st.st_mode & 07777)};
    return "";
  }
}

fs::path folder_of(const std::string& path) {
  const fs::path parent = fs::path(path).parent_path();
  return parent.empty() ? fs::path(".") : parent;
}

// Creates a unique temporary file named after `target` in `folder`: hidden, and short enough
// for any file system whatever the target's name. Returns its descriptor (-1 and errno on
// failure) and sets `tmp` to its path.
int make_temporary(const fs::path& folder, const std::string& target, std::string& tmp) {
  const std::string name = fs::path(target).filename().string().substr(0, 200);
  std::string pattern = (folder / ("." + name + ".tmp-XXXXXX")).string();
  std::vector<char> buf(pattern.begin(), pattern.end());
  buf.push_back('\0');
  const int fd = mkstemp(buf.data());
  if (fd >= 0) tmp = buf.data();
  return fd;
}

// What a new file gets: read and write for all, less the umask (as open(2) gives).
mode_t new_file_mode() {
  static const mode_t mask = [] {
    const mode_t m = umask(0);
    umask(m);
    return m;
  }();
  return 0666 & ~mask;
}

// Whether a file can be created in `folder`: creates one and removes it. Returns the problem.
std::string probe(const fs::path& folder) {
  std::string tmp;
  const int fd = make_temporary(folder, "drape-probe", tmp);
  if (fd < 0) return std::strerror(errno);
  close(fd);
  unlink(tmp.c_str());
  return "";
}

[[noreturn]] void refuse(const std::string& option, const std::string& file,
                         const std::string& problem) {
  throw InputError(option + " " + file, problem);
}

}  // namespace

void check_output(const std::string& option, const std::string& file) {
  auto refuse = [&](const std::string& problem) { io::refuse(option, file, problem); };
  Target t;
  if (const std::string problem = resolve(file, t); !problem.empty()) refuse(problem);
  switch (t.kind) {
    case Kind::standard_output:
      return;
    case Kind::folder:
      io::refuse(option, file, "is a folder; name a file");
    case Kind::special:
      if (access(t.path.c_str(), W_OK) != 0)
        refuse(std::string("cannot be written: ") + std::strerror(errno));
      return;
    case Kind::regular:
      if (access(t.path.c_str(), W_OK) != 0)
        refuse(std::string("cannot be written: ") + std::strerror(errno));
      break;
    case Kind::absent:
      break;
  }
  const fs::path folder = folder_of(t.path);
  std::error_code ec;
  if (!fs::exists(folder, ec)) refuse("the folder " + folder.string() + " does not exist");
  if (!fs::is_directory(folder, ec)) refuse(folder.string() + " is not a folder");
  if (const std::string problem = probe(folder); !problem.empty())
    refuse("cannot write in the folder " + folder.string() + ": " + problem);
}

void check_output_folder(const std::string& option, const std::string& folder) {
  auto refuse = [&](const std::string& problem) { io::refuse(option, folder, problem); };
  if (folder.empty()) refuse("the path is empty");
  if (folder == "-") refuse("needs a folder; - (standard output) takes a single file");
  // The folder, or else the nearest of its parents that exists: the one to write or create in.
  std::error_code ec;
  fs::path existing = folder;
  while (!fs::exists(existing, ec)) {
    const fs::path parent = existing.parent_path();
    existing = parent.empty() || parent == existing ? fs::path(".") : parent;
  }
  if (!fs::is_directory(existing, ec))
    refuse(existing == fs::path(folder) ? "exists and is not a folder"
                                        : existing.string() + " is not a folder");
  if (const std::string problem = probe(existing); !problem.empty())
    refuse("cannot write in the folder " + existing.string() + ": " + problem);
}

OutputFile::OutputFile(const std::string& file) : file_(file) {
  Target t;
  if (const std::string problem = resolve(file, t); !problem.empty())
    throw OutputError(file + ": cannot write: " + problem);
  target_ = t.path;
  switch (t.kind) {
    case Kind::folder:
      throw OutputError(file + ": cannot write: it is a folder");
    case Kind::standard_output:
    case Kind::special: {
      struct sigaction ignore {};
      ignore.sa_handler = SIG_IGN;
      pipe_ignored_ = sigaction(SIGPIPE, &ignore, &old_pipe_) == 0;
      stdout_ = t.kind == Kind::standard_output;
      f_ = stdout_ ? stdout : std::fopen(target_.c_str(), "wb");
      if (!f_) fail(errno);
      break;
    }
    case Kind::regular:
    case Kind::absent: {
      if (t.kind == Kind::regular && access(target_.c_str(), W_OK) != 0) fail(errno);
      mode_ = t.kind == Kind::regular ? t.mode : new_file_mode();
      const int fd = make_temporary(folder_of(target_), target_, tmp_);
      if (fd < 0) fail(errno);
      f_ = fdopen(fd, "wb");
      if (!f_) {
        const int error = errno;
        close(fd);
        fail(error);
      }
      break;
    }
  }
  errno = 0;  // so that commit() reports the errno of a failed write, not of an earlier call
}

OutputFile::~OutputFile() {
  discard();
}

void OutputFile::discard() {
  if (f_ && !stdout_) std::fclose(f_);
  f_ = nullptr;
  if (!tmp_.empty()) unlink(tmp_.c_str());
  tmp_.clear();
  if (pipe_ignored_) sigaction(SIGPIPE, &old_pipe_, nullptr);
  pipe_ignored_ = false;
}

void OutputFile::fail(int error) {
  discard();
  const std::string where =
      target_.empty() || target_ == file_ || stdout_ ? file_ : file_ + " (" + target_ + ")";
  throw OutputError(where + ": cannot write: " + std::strerror(error));
}

void OutputFile::commit() {
  int error = 0;
  if (std::fflush(f_) != 0 || std::ferror(f_)) error = errno ? errno : EIO;
  if (stdout_) {
    f_ = nullptr;
  } else {
    if (!error && !tmp_.empty() && fchmod(fileno(f_), mode_) != 0) error = errno;
    FILE* f = f_;
    f_ = nullptr;
    if (std::fclose(f) != 0 && !error) error = errno ? errno : EIO;
    if (!error && !tmp_.empty() && std::rename(tmp_.c_str(), target_.c_str()) != 0) error = errno;
  }
  if (error) fail(error);
  tmp_.clear();
  discard();
}

void write_all(FILE* f, const void* data, size_t bytes, const std::string& file) {
  if (bytes > 0 && std::fwrite(data, 1, bytes, f) != bytes)
    throw OutputError(file + ": cannot write: " + std::strerror(errno));
}

void write_output(const std::string& file, const std::string& bytes) {
  OutputFile out(file);
  std::fwrite(bytes.data(), 1, bytes.size(), out.get());
  out.commit();
}

std::string file_name_from(const std::string& text) {
  std::string name;
  for (const char c : text.substr(0, 64)) {
    const bool kept = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                      c == '.' || c == '_' || c == '-' || c == '+';
    name += kept ? c : '_';
  }
  for (char& c : name) {
    if (c != '.') break;
    c = '_';
  }
  return name.empty() ? "untitled" : name;
}

}  // namespace drape::io
