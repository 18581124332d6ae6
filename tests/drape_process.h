// Runs the `drape` command as a user would, for the tests that check what it writes.
#pragma once

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace drape::testing_support {

struct CommandResult {
  int code = -1;       ///< exit code, or -1 if it did not exit normally
  std::string output;  ///< stdout and stderr together
};

/// A shell command, with its exit code and output.
inline CommandResult run_shell(const std::string& command_line) {
  const std::string command = command_line + " 2>&1";
  CommandResult r;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buf;
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), pipe)) > 0) r.output.append(buf.data(), n);
  const int status = pclose(pipe);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

/// `drape ARGS`, with its exit code and output.
inline CommandResult run_drape(const std::string& args) {
  return run_shell(std::string(DRAPE_EXE) + " " + args);
}

/// `drape ARGS` in the background, sent `signal` ("INT", "TERM") after `seconds`; its exit code.
/// With job control on (set -m): a shell without it starts background commands with SIGINT
/// ignored, so a signal sent before drape installs its handler (a slow start under the
/// sanitizers) would be lost and the run would go on to its end.
inline int run_drape_interrupted(const std::string& args, const char* signal, double seconds) {
  const std::string command = "set -m; " + std::string(DRAPE_EXE) + " " + args +
                              " >/dev/null 2>&1 & pid=$!; sleep " + std::to_string(seconds) +
                              "; kill -" + signal + " $pid; wait $pid";
  const int status = std::system(("bash -c '" + command + "'").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/// A shipped scene's path.
inline std::string shipped_scene(const std::string& name) {
  return std::string(DRAPE_SOURCE_DIR) + "/scenes/" + name + ".json";
}

}  // namespace drape::testing_support
