// drape: a cloth simulator. `drape run SCENE` simulates headless; `drape --help` lists the rest.
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "app/commands.h"

namespace drape::app {

std::string scenes_dir() {
  if (const char* env = std::getenv("DRAPE_SCENES")) return env;
  std::error_code ec;
  if (std::filesystem::is_directory("scenes", ec)) return "scenes";
  return DRAPE_SCENES_DIR;
}

}  // namespace drape::app

int main(int argc, char** argv) {
  using namespace drape::app;
  CLI::App app("drape: a fast, stable cloth simulator (mass-spring)", "drape");
  app.set_version_flag("--version", DRAPE_VERSION);
  app.require_subcommand(1);
  const auto run = add_run_command(app);
  const auto compare = add_compare_command(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : kExitBadInput;
  }
  for (const auto& command : {run, compare}) {
    const int code = command();
    if (code >= 0) return code;
  }
  return kExitBadInput;
}
