// `drape compare SCENE`: run one scene with each method and print the figures side by side,
// so the trade-offs (time per frame, substeps, stretch, rest, contacts) read as one table.
#include <algorithm>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include <omp.h>

#include "app/commands.h"
#include "app/options.h"
#include "app/runner.h"
#include "app/terminal.h"
#include "drape/error.h"
#include "io/scene_io.h"
#include "io/shown_text.h"

namespace drape::app {

namespace {

struct CompareOptions {
  std::string scene;
  std::vector<std::string> methods;  // empty: all
  std::optional<double> seconds;
  std::vector<std::string> sets;
  int threads = 0;
  bool markdown = false;
  bool force = false;
};

struct Row {
  std::string method;
  std::string status;  // "ok", "diverged at frame N", "refused: ..."
  double ms = 0.0;
  int substeps = 0;
  Diagnostics d;
};

std::string percent(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3f%%", 100.0 * x);
  return buf;
}

std::string number(const char* format, double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, format, x);
  return buf;
}

void print_table(const std::vector<Row>& rows, bool markdown) {
  const std::vector<std::string> head{"method",        "ms/frame",    "substeps",
                                      "max strain",    "mean strain", "kinetic J",
                                      "penetration m", "finite",      "status"};
  std::vector<std::vector<std::string>> cells;
  for (const Row& r : rows) {
    const bool ran = r.status.rfind("refused", 0) != 0;
    cells.push_back({r.method, ran ? number("%.3f", r.ms) : "-",
                     ran ? std::to_string(r.substeps) : "-", ran ? percent(r.d.max_strain) : "-",
                     ran ? percent(r.d.mean_strain) : "-",
                     ran ? number("%.3g", r.d.kinetic_energy) : "-",
                     ran ? number("%.3g", r.d.max_penetration) : "-",
                     ran ? (r.d.finite ? "yes" : "no") : "-", r.status});
  }
  std::vector<size_t> width(head.size());
  for (size_t c = 0; c < head.size(); ++c) {
    width[c] = head[c].size();
    for (const auto& row : cells) width[c] = std::max(width[c], row[c].size());
  }
  auto line = [&](const std::vector<std::string>& row) {
    std::string out = markdown ? "|" : "";
    for (size_t c = 0; c < row.size(); ++c) {
      std::string cell = row[c];
      // Text left, figures right.
      const bool left = c == 0 || c + 1 == row.size();
      const std::string pad(width[c] - cell.size(), ' ');
      cell = left ? cell + pad : pad + cell;
      out += markdown ? " " + cell + " |" : (c ? "  " : "") + cell;
    }
    std::printf("%s\n", out.c_str());
  };
  line(head);
  if (markdown) {
    std::string rule = "|";
    for (size_t c = 0; c < head.size(); ++c) {
      const bool left = c == 0 || c + 1 == head.size();
      rule += (left ? ":" : "") + std::string(width[c] + 1, '-') + (left ? "" : ":") + "|";
    }
    std::printf("%s\n", rule.c_str());
  }
  for (const auto& row : cells) line(row);
}

int compare(const CompareOptions& o) {
  use_threads(o.threads);
  std::vector<Method> methods;
  if (o.methods.empty()) methods.assign(std::begin(kAllMethods), std::end(kAllMethods));
  for (const std::string& name : o.methods) {
    const std::optional<Method> m = method_from_string(name);
    if (!m) {
      std::fprintf(stderr, "drape: error: --methods: unknown method \"%s\"; expected %s\n",
                   io::shown(name).c_str(), method_names().c_str());
      return kExitBadInput;
    }
    methods.push_back(*m);
  }
  std::vector<std::string> sets = o.sets;
  if (o.seconds) sets.push_back("duration=" + exact_number(*o.seconds));
  const std::string source = io::source_name(o.scene);

  // Each method's scene is checked with that method set, after the overrides: a key may be
  // valid for one method and not another (solver.precision "single" is xpbd's alone). A method
  // its scene refuses gets a row saying why; a scene no method takes is bad input.
  std::vector<Row> rows(methods.size());
  std::vector<std::optional<SceneDef>> defs(methods.size());
  std::vector<std::string> problems;
  try {
    const nlohmann::json scene = io::load_scene_json(o.scene, sets);
    for (size_t k = 0; k < methods.size(); ++k) {
      rows[k].method = to_string(methods[k]);
      nlohmann::json j = scene;
      io::apply_override(j, std::string("solver.method=") + to_string(methods[k]));
      try {
        defs[k] = io::parse_scene(j, source, io::scene_folder(o.scene));
      } catch (const InputError& e) {
        rows[k].status = "refused: " + e.problem();
        if (std::find(problems.begin(), problems.end(), e.what()) == problems.end())
          problems.push_back(e.what());
        continue;
      }
      if (!o.force) {
        try {
          check_memory(*defs[k]);
        } catch (const InputError& e) {
          throw InputError(source + ": " + e.path(), e.problem());
        }
      }
    }
  } catch (const InputError& e) {
    std::fprintf(stderr, "drape: error: %s\n", e.what());
    return kExitBadInput;
  }
  const auto first = std::find_if(defs.begin(), defs.end(), [](const auto& d) { return d; });
  if (first == defs.end()) {
    for (const std::string& p : problems) std::fprintf(stderr, "drape: error: %s\n", p.c_str());
    return kExitBadInput;
  }
  const SceneDef& def = **first;
  const int64_t frames = frame_count(def);

  install_interrupt_handlers();
  bool any_ran = false;
  for (size_t k = 0; k < methods.size() && !interrupt_signal(); ++k) {
    Row& row = rows[k];
    if (!defs[k]) continue;
    std::optional<Simulation> sim;
    try {
      sim.emplace(*defs[k]);
      if (!o.force) check_work(*sim, frames);
    } catch (const InputError& e) {
      row.status = "refused: " + e.problem();
      continue;
    }
    RunHooks hooks;
    hooks.threads = o.threads;
    hooks.progress_label = io::shown(def.name, 30) + " " + row.method;  // only on a terminal
    const RunResult run = run_frames(*sim, frames, hooks);
    any_ran = true;
    row.ms = run.median_ms();
    row.substeps = sim->substeps_per_frame();
    row.d = sim->diagnostics();
    row.status = run.status == RunStatus::ok ? "ok"
                 : sim->diverged() ? "diverged at frame " + std::to_string(sim->diverged_frame())
                                   : "interrupted";
  }
  // The methods an interrupt left unrun have no row.
  std::erase_if(rows, [](const Row& r) { return r.status.empty(); });
  const std::string cloth = def.cloth.mesh ? "mesh " + io::shown(def.cloth.mesh_file) + ", " +
                                                 std::to_string(particle_count(def.cloth))
                                           : std::to_string(def.cloth.cols) + "x" +
                                                 std::to_string(def.cloth.rows);
  std::printf("%s: %s particles, %lld frames of %.4g s (%.3g s simulated), %d thread(s)\n",
              io::shown(def.name).c_str(), cloth.c_str(), static_cast<long long>(frames),
              def.solver.dt,
              static_cast<double>(frames) * def.solver.dt, omp_get_max_threads());
  print_table(rows, o.markdown);
  if (int s = interrupt_signal()) return interrupt_exit_code(s);
  return any_ran ? kExitOk : kExitBadInput;
}

}  // namespace

std::function<int()> add_compare_command(CLI::App& app) {
  auto o = std::make_shared<CompareOptions>();
  CLI::App* cmd = app.add_subcommand(
      "compare", "Run a scene with each method and print their figures side by side");
  cmd->add_option("scene", o->scene, "Scene file (JSON), or - to read it from standard input")
      ->required();
  cmd->add_option("--methods", o->methods, "Methods to compare, in order (default: all)")
      ->delimiter(',')
      ->take_all();
  cmd->add_option("--seconds", o->seconds, "Simulated duration in s (overrides the scene's)")
      ->check(finite_range(0.0, 1e7));
  cmd->add_option("--set", o->sets, "Override a scene key: KEY=VALUE, e.g. cloth.mass=2")
      ->take_all()
      ->allow_extra_args(false);
  add_threads_option(cmd, o->threads);
  cmd->add_flag("--markdown", o->markdown, "Print the table as Markdown");
  cmd->add_flag("--force", o->force, "Run beyond the memory and work budgets");
  cmd->footer(exit_codes_help({kExitOk, kExitBadInput, 129, 130, 143}) +
              "\nA method that diverges or is refused says so in its row; the exit code is 0.");
  return [cmd, o] { return cmd->parsed() ? compare(*o) : -1; };
}

}  // namespace drape::app
