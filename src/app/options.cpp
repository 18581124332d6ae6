#include "app/options.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "app/commands.h"
#include "drape/error.h"

namespace drape::app {

void add_threads_option(CLI::App* cmd, int& threads) {
  cmd->add_option("--threads", threads, "Threads to use (default: all cores)")
      ->check(CLI::Range(1, 1024));
}

void use_threads(int threads) {
#ifdef _OPENMP
  if (threads > 0) omp_set_num_threads(threads);
#else
  (void)threads;
#endif
}

CLI::Validator finite_range(double lo, double hi) {
  char description[64];
  std::snprintf(description, sizeof description, "NUMBER in [%g, %g]", lo, hi);
  return CLI::Validator(
      [lo, hi, text = std::string(description)](std::string& value) -> std::string {
        char* end = nullptr;
        const double x = std::strtod(value.c_str(), &end);
        if (value.empty() || *end != '\0' || !std::isfinite(x) || x < lo || x > hi)
          return "\"" + value + "\" is not a " + text;
        return "";
      },
      description);
}

const CLI::Validator kNonEmpty(
    [](std::string& value) -> std::string {
      return value.empty() ? "is empty; give a path, or leave the option out" : "";
    },
    "");

void parse_size(const std::string& option, const std::string& text, int& width, int& height) {
  // Digits, an x, digits: nothing before, between or after.
  const size_t x = text.find_first_of("xX");
  auto digits = [](const std::string& t) {
    return !t.empty() && t.size() <= 5 &&
           std::all_of(t.begin(), t.end(), [](unsigned char c) { return std::isdigit(c); });
  };
  if (x != std::string::npos && digits(text.substr(0, x)) && digits(text.substr(x + 1))) {
    width = std::stoi(text.substr(0, x));
    height = std::stoi(text.substr(x + 1));
    if (width >= 16 && height >= 16 && width <= 8192 && height <= 8192) return;
  }
  throw InputError(option,
                   "\"" + text + "\" is not a size WIDTHxHEIGHT in pixels, each 16 to 8192");
}

std::string exact_number(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", x);
  return text;
}

void check_not_the_scene(const std::string& option, const std::string& output,
                         const std::string& scene) {
  std::error_code ec;
  if (output != "-" && scene != "-" && std::filesystem::equivalent(output, scene, ec))
    throw InputError(option + " " + output,
                     "is the scene file; writing it would destroy the scene");
}

namespace {

struct ExitCode {
  int code;
  const char* meaning;
};

constexpr ExitCode kExitCodes[] = {
    {kExitOk, "success"},
    {kExitBadInput, "bad input (the message names it); nothing was run or written"},
    {kExitDiverged, "the simulation diverged (frame, reason and a hint are printed)"},
    {kExitNoGraphics, "no display, or no OpenGL 3.3 context"},
    {kExitOutputFailed, "an output could not be written (after the summary)"},
    {129, "stopped by SIGHUP (terminal closed) at the next substep (a second one: at once)"},
    {130, "stopped by SIGINT (Ctrl-C) at the next substep (a second one: at once)"},
    {143, "stopped by SIGTERM at the next substep (a second one: at once)"},
};

}  // namespace

std::string exit_codes_help(const std::vector<int>& codes) {
  std::string text = "Exit codes:";
  for (const ExitCode& e : kExitCodes) {
    if (std::find(codes.begin(), codes.end(), e.code) == codes.end()) continue;
    char line[160];
    std::snprintf(line, sizeof line, "\n  %-4d %s", e.code, e.meaning);
    text += line;
  }
  return text;
}

}  // namespace drape::app
