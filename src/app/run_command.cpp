// `drape run SCENE`: simulate headless, print a summary, write stats and mesh exports.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "app/commands.h"
#include "app/exports.h"
#include "app/options.h"
#include "app/runner.h"
#include "app/terminal.h"
#include "drape/error.h"
#include "drape/self_intersections.h"
#include "io/output_file.h"
#include "io/scene_io.h"
#include "io/shown_text.h"

namespace drape::app {

namespace fs = std::filesystem;

namespace {

struct RunOptions {
  std::string scene;
  std::optional<double> seconds;
  std::vector<std::string> sets;
  std::string stats;
  std::string export_path;
  std::string format;  // empty: from --export's name
  int every = 1;
  int threads = 0;
  bool quiet = false;
  bool force = false;
};

int run(const RunOptions& o) {
  use_threads(o.threads);
  std::vector<std::string> sets = o.sets;
  if (o.seconds) sets.push_back("duration=" + exact_number(*o.seconds));
  const std::string source = io::source_name(o.scene);

  // Everything that can be checked before the run is, so a mistake costs no simulation and
  // leaves nothing behind: the scene, the outputs, the budgets; then the export folder is made.
  using clock = std::chrono::steady_clock;
  std::optional<Simulation> sim;
  int64_t frames = 0, replaced = 0;
  double setup_ms = 0.0;
  ExportTarget target;
  try {
    const SceneDef def = io::load_scene(o.scene, sets);
    frames = frame_count(def);
    if (!o.stats.empty()) {
      io::check_output("--stats", o.stats);
      check_not_the_scene("--stats", o.stats, o.scene);
      // Not there yet, the export folder passes the check above, and is made before the end.
      const auto normal = [](const std::string& p) {
        const fs::path n = fs::path(p).lexically_normal();
        return n.has_filename() ? n : n.parent_path();
      };
      if (!o.export_path.empty() && normal(o.stats) == normal(o.export_path))
        throw InputError("--stats " + o.stats, "is the --export folder; name a file");
    }
    if (!o.export_path.empty()) target = resolve_export(o.export_path, o.format, o.scene, o.every);
    const auto t0 = clock::now();
    try {
      if (!o.force) check_memory(def);
      sim.emplace(def);
      if (!o.force) check_work(*sim, frames);
    } catch (const InputError& e) {
      throw InputError(source + ": " + e.path(), e.problem());
    }
    setup_ms = std::chrono::duration<double, std::milli>(clock::now() - t0).count();
    if (!o.export_path.empty()) {
      check_export(target, *sim, frames, o.force);
      replaced = prepare_export(target);
    }
  } catch (const InputError& e) {
    std::fprintf(stderr, "drape: error: %s\n", e.what());
    return kExitBadInput;
  }

  std::optional<Exporter> exporter;
  RunHooks hooks;
  hooks.threads = o.threads;
  if (!o.quiet) hooks.progress_label = io::shown(sim->def().name, 30);
  if (!o.export_path.empty()) {
    exporter.emplace(target, frames, "drape " DRAPE_VERSION);
    hooks.after_frame = [&](const Simulation& s) { exporter->after_frame(s); };
  }
  install_interrupt_handlers();
  RunResult result = run_frames(*sim, frames, hooks);
  result.setup_ms = setup_ms;
  std::vector<std::string> output_errors;
  // A stopped run still exports where it stopped; caches are completed here.
  if (exporter) {
    try {
      exporter->finish(*sim, result);
    } catch (const io::OutputError& e) {
      output_errors.push_back(e.what());
    }
  }
  // Counting the self-intersections costs about a frame or more: once, for the stats and the
  // summary both.
  std::optional<int64_t> self_intersections;
  if (!o.stats.empty()) {
    const nlohmann::json stats = stats_json(*sim, result);
    self_intersections = stats["self_intersections"].get<int64_t>();
    try {
      io::write_output(o.stats, json_text(stats));
    } catch (const io::OutputError& e) {
      output_errors.push_back(e.what());
    }
  }

  // The summary goes to standard error when the stats take standard output.
  FILE* out = o.stats == "-" ? stderr : stdout;
  const Diagnostics d = sim->diagnostics();
  if (!o.quiet) {
    if (!self_intersections)
      self_intersections = count_self_intersections(sim->model().triangles, sim->state().x);
    std::fprintf(
        out,
        "%s: %lld frames (%.2f s simulated) in %.2f s, %.3f ms/frame (median), %d substeps/frame, "
        "method %s\n"
        "  %d particles, %zu springs; kinetic energy %.3g J, strain max %.2f%% mean %.2f%%, "
        "penetration %.3g m, pin drift %.3g m, self-intersections %lld\n",
        io::shown(sim->def().name).c_str(), static_cast<long long>(result.frames), sim->time(),
        result.wall_seconds, result.median_ms(), sim->substeps_per_frame(),
        method_text(*sim).c_str(), sim->model().size(), sim->model().springs.size(),
        d.kinetic_energy, 100.0 * d.max_strain, 100.0 * d.mean_strain, d.max_penetration,
        d.pinned_drift, static_cast<long long>(*self_intersections));
    if (exporter) {
      std::fprintf(out, "  exported %s", exporter->summary().c_str());
      if (replaced > 0)
        std::fprintf(out, ", in place of an earlier run's %lld", static_cast<long long>(replaced));
      std::fprintf(out, "\n");
    }
    if (!o.stats.empty() && output_errors.empty() && o.stats != "-")
      std::fprintf(out, "  stats written to %s\n", o.stats.c_str());
    std::fflush(out);
  }
  int code = exit_code(source, *sim, result, "stats and exports so far are kept");
  for (const std::string& e : output_errors) std::fprintf(stderr, "drape: error: %s\n", e.c_str());
  return output_errors.empty() ? code : kExitOutputFailed;
}

}  // namespace

std::function<int()> add_run_command(CLI::App& app) {
  auto o = std::make_shared<RunOptions>();
  CLI::App* cmd = app.add_subcommand("run", "Simulate a scene headless and report what happened");
  cmd->add_option("scene", o->scene, "Scene file (JSON), or - to read it from standard input")
      ->required();
  cmd->add_option("--seconds", o->seconds, "Simulated duration in s (overrides the scene's)")
      ->check(finite_range(0.0, 1e7));
  cmd->add_option("--set", o->sets, "Override a scene key: KEY=VALUE, e.g. cloth.mass=2")
      ->take_all()
      ->allow_extra_args(false);
  cmd->add_option("--stats", o->stats,
                  "Write run statistics as JSON to this file (- for standard output)")
      ->check(kNonEmpty);
  CLI::Option* export_dir =
      cmd->add_option("--export", o->export_path,
                      "Write one mesh per exported frame to this folder, or one animation cache "
                      "of the run to this FILE.pc2 or FILE.glb")
          ->check(kNonEmpty);
  cmd->add_option("--format", o->format,
                  "Export format: obj or ply (files per frame), pc2 or glb (one cache; with a "
                  "folder, named after the scene file). Default: from --export's name, else obj")
      ->check(CLI::IsMember({"obj", "ply", "pc2", "glb"}))
      ->needs(export_dir);
  cmd->add_option("--every", o->every, "Export every Nth frame (and always the last)")
      ->check(CLI::Range(1, 1 << 30))
      ->needs(export_dir)
      ->capture_default_str();
  add_threads_option(cmd, o->threads);
  cmd->add_flag("--quiet", o->quiet, "No progress bar and no summary");
  cmd->add_flag("--force", o->force,
                "Run beyond the memory and work budgets, and export into a folder that holds an "
                "earlier run's frames (which are removed first)");
  cmd->footer(
      exit_codes_help({kExitOk, kExitBadInput, kExitDiverged, kExitOutputFailed, 129, 130, 143}));
  return [cmd, o] { return cmd->parsed() ? run(*o) : -1; };
}

}  // namespace drape::app
