// `drape view [SCENE]`: the interactive viewer (see app/viewer.h), and its scripted form used by
// the smoke tests and for screenshots: --frames N --screenshot FILE [--drag x0,y0,x1,y1].
#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "app/commands.h"
#include "app/options.h"
#include "app/runner.h"
#include "app/viewer.h"
#include "drape/error.h"
#include "io/output_file.h"
#include "io/scene_io.h"
#include "render/offscreen.h"

namespace drape::app {

namespace {

struct ViewCommandOptions {
  std::string scene;
  std::vector<std::string> sets;
  std::string size = "1280x720";
  int64_t frames = 0;
  std::string screenshot;
  std::string report;
  std::string drag;
  bool carry = false;
  int threads = 0;
  bool no_vsync = false;
  bool no_panel = false;
  bool force = false;
};

std::array<double, 4> parse_drag(const std::string& text) {
  std::array<double, 4> v{};
  std::istringstream in(text);
  char comma = 0;
  if (in >> v[0] >> comma && comma == ',' && in >> v[1] >> comma && comma == ',' &&
      in >> v[2] >> comma && comma == ',' && in >> v[3] && (in >> std::ws).eof())
    return v;
  throw InputError("--drag", "\"" + text + "\" is not four window coordinates x0,y0,x1,y1");
}

int view(const ViewCommandOptions& c) {
  ViewerOptions o;
  o.scene =
      c.scene.empty() ? (std::filesystem::path(scenes_dir()) / "hang.json").string() : c.scene;
  o.sets = c.sets;
  o.vsync = !c.no_vsync && c.frames == 0;  // scripted runs go as fast as they can
  o.panel = !c.no_panel;
  o.frames = c.frames;
  o.screenshot = c.screenshot;
  o.report = c.report;
  o.threads = c.threads;
  SceneDef def;
  try {
    parse_size("--size", c.size, o.width, o.height);
    if (!c.drag.empty()) o.drag = parse_drag(c.drag);
    if (c.carry && !o.drag) throw InputError("--carry", "needs --drag x0,y0,x1,y1");
    o.carry = c.carry;
    if ((!o.screenshot.empty() || o.drag || !o.report.empty()) && o.frames <= 0)
      throw InputError("--frames", "--screenshot, --drag and --report need --frames N (N > 0)");
    def = io::load_scene(o.scene, o.sets);
    for (const auto& [option, file] :
         {std::pair{"--screenshot", o.screenshot}, {"--report", o.report}}) {
      if (file.empty()) continue;
      io::check_output(option, file);
      check_not_the_scene(option, file, o.scene);
    }
    if (!c.force) {
      try {
        check_memory(def);
      } catch (const InputError& e) {
        throw InputError(io::source_name(o.scene) + ": " + e.path(), e.problem());
      }
      check_memory(def, render::estimated_picture_bytes(o.width, o.height), "--size " + c.size);
    }
  } catch (const InputError& e) {
    std::fprintf(stderr, "drape: error: %s\n", e.what());
    return kExitBadInput;
  }
  const char* x11 = std::getenv("DISPLAY");
  const char* wayland = std::getenv("WAYLAND_DISPLAY");
  if ((!x11 || !*x11) && (!wayland || !*wayland)) {
    std::fprintf(stderr,
                 "drape view: no display (DISPLAY is not set); draw pictures without one with "
                 "`drape render %s`, or run the viewer under `xvfb-run -a drape view`\n",
                 o.scene.c_str());
    return kExitNoGraphics;
  }
  return run_viewer(o, def);
}

}  // namespace

std::function<int()> add_view_command(CLI::App& app) {
  auto o = std::make_shared<ViewCommandOptions>();
  CLI::App* cmd = app.add_subcommand("view", "Open the interactive viewer on a scene");
  cmd->add_option("scene", o->scene,
                  "Scene file (JSON), or - to read it from standard input; default: the shipped "
                  "scenes/hang.json");
  cmd->add_option("--set", o->sets, "Override a scene key: KEY=VALUE, e.g. cloth.mass=2")
      ->take_all()
      ->allow_extra_args(false);
  cmd->add_option("--size", o->size, "Window size WIDTHxHEIGHT")->capture_default_str();
  cmd->add_option("--frames", o->frames, "Run this many frames, then exit (scripted use)")
      ->check(CLI::Range(int64_t{1}, int64_t{1} << 40));
  cmd->add_option("--screenshot", o->screenshot, "With --frames: save the last frame as PNG")
      ->check(kNonEmpty);
  cmd->add_option("--report", o->report,
                  "With --frames: write frame rate and drag figures as JSON (- for standard "
                  "output)")
      ->check(kNonEmpty);
  cmd->add_option("--drag", o->drag,
                  "With --frames: press at x0,y0, drag to x1,y1 (window units), hold to the end");
  cmd->add_flag("--carry", o->carry,
                "With --drag: hold Shift, carrying the collider under x0,y0 instead of a particle");
  add_threads_option(cmd, o->threads);
  cmd->add_flag("--no-vsync", o->no_vsync, "Draw as fast as possible");
  cmd->add_flag("--no-panel", o->no_panel, "Hide the control panel");
  cmd->add_flag("--force", o->force, "Open a cloth, or a window, beyond the memory budget");
  cmd->footer(exit_codes_help(
      {kExitOk, kExitBadInput, kExitDiverged, kExitNoGraphics, kExitOutputFailed, 129, 130, 143}));
  return [cmd, o] { return cmd->parsed() ? view(*o) : -1; };
}

}  // namespace drape::app
