// drape: a cloth simulator. `drape run SCENE` simulates headless; `drape --help` lists the rest.
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "app/commands.h"
#include "drape/error.h"

namespace drape::app {

std::string data_dir(const std::string& name) {
  std::string env_name = "DRAPE_" + name;
  for (char& c : env_name) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  if (const char* env = std::getenv(env_name.c_str())) return env;
  std::error_code ec;
  if (std::filesystem::is_directory(name, ec)) return name;
  return std::string(DRAPE_SOURCE_DIR) + "/" + name;
}

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

}  // namespace drape::app

int main(int argc, char** argv) {
  using namespace drape::app;
  CLI::App app("drape: a fast, stable cloth simulator (mass-spring)", "drape");
  app.set_version_flag("--version", DRAPE_VERSION);
  app.require_subcommand(1);
  std::vector<std::function<int()>> commands{add_run_command(app), add_compare_command(app),
                                              add_bench_command(app), add_mesh_command(app)};
#ifdef DRAPE_HAVE_VIEWER
  commands.push_back(add_view_command(app));
#endif
#ifdef DRAPE_HAVE_RENDER
  commands.push_back(add_render_command(app));
#endif
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : kExitBadInput;
  }
  for (const auto& command : commands) {
    const int code = command();
    if (code >= 0) return code;
  }
  return kExitBadInput;
}
