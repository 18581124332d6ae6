// drape: a cloth simulator. `drape run SCENE` simulates headless; `drape --help` lists the rest.
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "app/commands.h"
#include "app/options.h"
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

}  // namespace drape::app

int main(int argc, char** argv) {
  using namespace drape::app;
  CLI::App app("drape: a fast, stable cloth simulator (mass-spring)", "drape");
  app.set_version_flag("--version", DRAPE_VERSION);
  app.require_subcommand(1);
  app.footer(exit_codes_help({kExitOk, kExitBadInput, kExitDiverged, kExitNoGraphics,
                              kExitOutputFailed, 129, 130, 143}) +
             "\nEach command's --help lists the codes it returns, and its options' defaults.");
  std::vector<std::function<int()>> commands{add_run_command(app), add_compare_command(app),
                                              add_bench_command(app), add_mesh_command(app),
                                              add_lab_command(app)};
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
