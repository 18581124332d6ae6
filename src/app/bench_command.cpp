// `drape bench`: the standard benchmark. Runs bench/scenes at several sizes, methods and thread
// counts, and reports speed beside quality: a fast run that stretches like rubber does not
// count.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "app/commands.h"
#include "app/options.h"
#include "app/runner.h"
#include "app/terminal.h"
#include "drape/error.h"
#include "drape/mesh.h"
#include "drape/self_intersections.h"
#include "io/output_file.h"
#include "io/scene_io.h"

namespace drape::app {

namespace fs = std::filesystem;

namespace {

struct BenchOptions {
  std::vector<std::string> scenes{"hang", "hang-lr", "drape",
                                  "drape-mesh"};  // pile, drape-sc on request
  std::vector<int> sizes{32, 64, 128, 256};
  std::vector<std::string> methods;                         // empty: all
  std::vector<std::string> precisions{"double", "single"};  // single: for xpbd only
  std::vector<int> threads{1, 2};
  int frames = 300;
  double max_updates = 3e10;  // skip runs estimated above this (about five minutes)
  bool search = true;         // position-based methods: find the fewest substeps that pass
  std::vector<int> stiff_sweeps{0, 2, 5, 10, 20};  // xpbd: tried with the substep search
  std::vector<int> line_passes{2, 3, 4, 5, 6, 8};  // xpbd: tried too (0: none, as sweeps)
  std::string out = "bench-results";
  bool force = false;                     // replace bench.json and bench.csv of an earlier run
  std::vector<std::string> xpbd_options;  // options given that only xpbd's runs read
};

constexpr const char* kResultFiles[] = {"bench.json", "bench.csv"};

// The substep counts tried, in order, when searching for the fewest that meet the bar: a
// ladder of ratio about 1.5, so the count found is within 1.5× of the least.
constexpr int kSubstepLadder[] = {4, 6, 9, 14, 21, 32, 48, 72, 108, 162, 243, 365, 548, 822, 1233};

// Methods whose quality is set by the substeps they are given (and which take any count).
bool searchable(const std::string& method) {
  return method == to_string(Method::xpbd);
}

// The quality bar a run must meet to count.
constexpr double kMaxStrain = 0.01;       // structural strain, max over the last second and last
constexpr double kMaxPenetration = 0.01;  // fraction of the sphere's radius
constexpr int kLastSecondFrames = 60;
// The cloth's self-intersections are counted at the start, every this many frames (half a second
// at 1/60 s) and after the last, outside the timed steps: one count costs one to several frames
// of a large cloth, so counting every frame would multiply a benchmark's wall time.
constexpr int kSelfIntersectionEvery = 30;

// A method in a precision; single precision is xpbd's alone.
struct Variant {
  std::string method, precision;
};

struct Row {
  std::string scene, method, precision, status = "ok";
  int n = 0, threads = 0, substeps = 0;
  int stiff_sweeps = 0;  ///< xpbd's solver.stiff_sweeps
  int line_passes = 0;   ///< xpbd's solver.line_passes
  int64_t particles = 0, frames = 0;
  double setup_ms = 0, ms_median = 0, ms_p10 = 0, ms_p90 = 0, rate = 0;
  double strain_last_second = 0, strain_last = 0, strain_p99 = 0, penetration = 0;
  int64_t self_intersections = 0;  ///< the most over the frames counted (kSelfIntersectionEvery)
  MemoryUse memory;                ///< after the run
  bool on_sphere = true, quality = false;
  int tries = 1;  ///< runs made to find the substeps (searched methods)
};

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  const size_t k = std::min(v.size() - 1, static_cast<size_t>(q * (v.size() - 1) + 0.5));
  std::nth_element(v.begin(), v.begin() + k, v.end());
  return v[k];
}

// Touching the sphere (within 1% of its radius of the contact distance) and not slid off it.
bool rests_on(const Simulation& sim, const Collider& sphere) {
  double closest = 1e300;
  Vec3 centroid = Vec3::Zero(), n;
  for (const Vec3& x : sim.state().x) {
    closest = std::min(closest, signed_distance(sphere, x, n) - sphere.thickness);
    centroid += x;
  }
  centroid /= sim.model().size();
  const Vec3 offset = centroid - sphere.center;
  const double horizontal = std::hypot(offset.x(), offset.z());
  return closest <= kMaxPenetration * sphere.radius && horizontal < sphere.radius;
}

// drape-mesh: the drape cloth (its size, place, mass and springs) as an irregular triangle mesh
// of n × n vertices, each inner one jittered in the plane and each quad split along a diagonal
// chosen at random (shapes::jittered_grid), generated here rather than read from a file.
ClothDef irregular_drape(const ClothDef& grid, int n) {
  ClothDef c = grid;
  const ClothDef defaults;
  c.width = defaults.width, c.height = defaults.height, c.cols = defaults.cols;
  c.rows = defaults.rows, c.origin = defaults.origin, c.orientation = defaults.orientation;
  c.mesh = std::make_shared<const ClothMesh>(shapes::jittered_grid(grid.width, n));
  c.mesh_file = "drape-mesh-" + std::to_string(n);
  c.transform.translate = grid.origin + Vec3(0.5 * grid.width, 0.0, 0.5 * grid.height);
  return c;
}

// One run; `substeps` 0 leaves the count to the method.
Row bench_one(const BenchOptions& o, const std::string& scene, int n, const Variant& v, int threads,
              int substeps, int stiff_sweeps, int line_passes) {
  Row row;
  row.scene = scene;
  row.n = n;
  row.method = v.method;
  row.precision = v.precision;
  row.threads = threads;
#ifdef _OPENMP
  omp_set_num_threads(threads);
#endif
  const bool long_range = scene == "hang-lr", mesh = scene == "drape-mesh";
  const bool self_collision = scene == "drape-sc";
  const std::string file = data_dir("bench") + "/scenes/" +
                           (long_range               ? "hang"
                            : mesh || self_collision ? "drape"
                                                     : scene) +
                           ".json";
  std::vector<std::string> sets = {"solver.method=" + v.method, "solver.precision=" + v.precision};
  if (!mesh)
    sets.push_back("cloth.resolution=[" + std::to_string(n) + "," + std::to_string(n) + "]");
  if (long_range) sets.push_back("cloth.long_range=true");
  if (self_collision) sets.push_back("cloth.self_collision=true");
  if (substeps > 0) sets.push_back("solver.substeps=" + std::to_string(substeps));
  if (stiff_sweeps > 0) sets.push_back("solver.stiff_sweeps=" + std::to_string(stiff_sweeps));
  if (line_passes > 0) sets.push_back("solver.line_passes=" + std::to_string(line_passes));
  row.stiff_sweeps = stiff_sweeps;
  row.line_passes = line_passes;
  std::optional<Simulation> sim;
  try {
    SceneDef def = io::load_scene(file, sets);
    if (mesh) def.cloth = irregular_drape(def.cloth, n);
    check_memory(def);
    const auto t0 = std::chrono::steady_clock::now();
    sim.emplace(def);
    row.setup_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    row.particles = sim->model().size();
    row.substeps = sim->substeps_per_frame();
    Budget budget;
    budget.updates = o.max_updates;
    check_work(*sim, o.frames, budget);
  } catch (const InputError& e) {
    row.status = std::string("skipped: ") + e.problem().substr(0, e.problem().find(';'));
    return row;
  }

  RunHooks hooks;
  hooks.threads = threads;
  hooks.after_frame = [&](const Simulation& s) {
    if (s.frame() > o.frames - kLastSecondFrames)
      row.strain_last_second = std::max(row.strain_last_second, s.diagnostics().max_strain);
    // With self-collision on, every frame: its bar is none at any frame.
    if (s.def().cloth.self_collision.enabled || s.frame() % kSelfIntersectionEvery == 0 ||
        s.frame() == o.frames)
      row.self_intersections = std::max(row.self_intersections,
                                        count_self_intersections(s.model().triangles, s.state().x));
  };
  const RunResult r = run_frames(*sim, o.frames, hooks);
  const Diagnostics d = sim->diagnostics();
  row.frames = r.frames;
  if (const AutoChoice* a = sim->auto_choice()) {  // what auto ended on, not what it was given
    row.precision = to_string(a->precision);
    row.substeps = a->substeps;
    row.stiff_sweeps = a->stiff_sweeps;
    row.line_passes = a->line_passes;
  }
  row.ms_median = r.median_ms();
  row.ms_p10 = percentile(r.frame_ms, 0.1);
  row.ms_p90 = percentile(r.frame_ms, 0.9);
  row.rate = row.ms_median > 0 ? row.particles * row.substeps / (row.ms_median * 1e-3) : 0.0;
  row.memory = sim->memory();
  row.strain_last = d.max_strain;
  row.strain_p99 = d.p99_strain;
  row.penetration = d.max_penetration;
  for (const Collider& c : sim->colliders()) {
    if (c.type != ColliderType::sphere) continue;
    row.on_sphere = row.on_sphere && rests_on(*sim, c);
    row.penetration = d.max_penetration / c.radius;  // as a fraction of the radius
  }
  if (r.status != RunStatus::ok) row.status = to_string(r.status);
  row.quality = row.status == "ok" && d.finite && row.strain_last_second <= kMaxStrain &&
                row.strain_last <= kMaxStrain && row.penetration <= kMaxPenetration &&
                row.on_sphere &&
                (!sim->def().cloth.self_collision.enabled || row.self_intersections == 0);
  return row;
}

// What the search settled on for one scene, size and variant.
struct Found {
  int substeps = 0, stiff_sweeps = 0, line_passes = 0;
};

// Whether run a is the better one to report: passing beats failing, then the faster of two
// that pass, or the less strained of two that fail.
bool better(const Row& a, const Row& b) {
  if (a.quality != b.quality) return a.quality;
  return a.quality ? a.ms_median < b.ms_median : a.strain_last_second < b.strain_last_second;
}

// The run to report: for a searched method, the cheapest run that meets the bar among, for each
// count of line passes and then of stiff sweeps, the fewest substeps on the ladder that do
// (found once per scene and size, on the first thread count, and reused: the results are the
// same for any thread count); otherwise the method's own count.
Row bench_best(const BenchOptions& o, const std::string& scene, int n, const Variant& v,
               int threads, Found& found) {
  if (!o.search || !searchable(v.method)) return bench_one(o, scene, n, v, threads, 0, 0, 0);
  if (found.substeps > 0)
    return bench_one(o, scene, n, v, threads, found.substeps, found.stiff_sweeps,
                     found.line_passes);
  // Each count of line passes (not on hang, whose pins have no attachments: line passes need
  // them), with none, one and two stiff sweeps after them, then each count of stiff sweeps, all
  // ascending: each costs more per substep than the last (a sweep after the passes costs a
  // fifth of a pass at 256², half at 128²).
  struct Try {
    int stiff_sweeps, line_passes;
  };
  std::vector<Try> kinds;
  if (scene != "hang")
    for (int lines : o.line_passes)
      if (lines > 0)
        for (int sweeps : {0, 1, 2}) kinds.push_back({sweeps, lines});
  for (int sweeps : o.stiff_sweeps) kinds.push_back({sweeps, 0});
  std::optional<Row> best, best_of_kind[2];  // overall; passing, of sweeps and of lines
  int tries = 0;
  for (const Try& kind : kinds) {
    std::optional<Row>& same = best_of_kind[kind.line_passes > 0];
    int tries_here = 0;
    double ms_per_substep = 0.0;  // of this count, from its last run
    for (int substeps : kSubstepLadder) {
      if (interrupt_signal()) break;
      // As many substeps with more sweeps or passes each cannot be cheaper than a run of the
      // same kind that passed, nor, by the cost per substep measured, than any that did.
      if (same && substeps >= same->substeps) break;
      if (best && best->quality && ms_per_substep * substeps >= best->ms_median) break;
      Row r = bench_one(o, scene, n, v, threads, substeps, kind.stiff_sweeps, kind.line_passes);
      ++tries;
      ++tries_here;
      const bool skipped = r.status.rfind("skipped", 0) == 0;
      if (skipped && tries_here > 1) break;  // past the work budget
      if (!skipped && r.substeps > 0) ms_per_substep = r.ms_median / r.substeps;
      if (!best || (!skipped && better(r, *best))) best = r;
      if (r.quality && (!same || better(r, *same))) same = r;
      if (r.quality || r.status != "ok") break;
    }
  }
  if (!best) return bench_one(o, scene, n, v, threads, 0, 0, 0);  // interrupted before any run
  best->tries = tries;
  if (best->substeps > 0) found = {best->substeps, best->stiff_sweeps, best->line_passes};
  return *best;
}

void print_table(const std::vector<Row>& rows) {
  std::printf("%-10s %5s %-11s %-6s %3s %8s %6s %5s %10s %9s %12s %6s %8s %8s %8s %8s %6s %s\n",
              "scene", "N", "method", "prec", "thr", "substeps", "sweeps", "lines", "ms/frame",
              "p10-p90", "part·sub/s", "B/part", "strain1s", "strain", "p99", "penetr.", "selfx",
              "quality");
  for (const Row& r : rows) {
    if (r.status.rfind("skipped", 0) == 0) {
      std::printf("%-10s %5d %-11s %-6s %3d  %s\n", r.scene.c_str(), r.n, r.method.c_str(),
                  r.precision.c_str(), r.threads, r.status.c_str());
      continue;
    }
    char spread[32];
    std::snprintf(spread, sizeof spread, "%.2f-%.2f", r.ms_p10, r.ms_p90);
    std::printf(
        "%-10s %5d %-11s %-6s %3d %8d %6d %5d %10.3f %9s %12.3g %6.0f %7.2f%% %7.2f%% %7.2f%% "
        "%7.2f%% %6lld %s\n",
        r.scene.c_str(), r.n, r.method.c_str(), r.precision.c_str(), r.threads, r.substeps,
        r.stiff_sweeps, r.line_passes, r.ms_median, spread, r.rate,
        r.memory.per_particle(r.particles), 100 * r.strain_last_second, 100 * r.strain_last,
        100 * r.strain_p99, 100 * r.penetration, static_cast<long long>(r.self_intersections),
        r.quality ? "yes" : (r.status == "ok" ? "no" : r.status.c_str()));
  }
}

nlohmann::json to_json(const Row& r) {
  return {{"scene", r.scene},
          {"n", r.n},
          {"method", r.method},
          {"precision", r.precision},
          {"threads", r.threads},
          {"status", r.status},
          {"particles", r.particles},
          {"substeps_per_frame", r.substeps},
          {"stiff_sweeps", r.stiff_sweeps},
          {"line_passes", r.line_passes},
          {"frames", r.frames},
          {"setup_ms", figure(r.setup_ms)},
          {"ms_per_frame_median", figure(r.ms_median)},
          {"ms_per_frame_p10", figure(r.ms_p10)},
          {"ms_per_frame_p90", figure(r.ms_p90)},
          {"particle_substeps_per_second", figure(r.rate)},
          {"bytes_per_particle", figure(r.memory.per_particle(r.particles))},
          {"state_bytes", r.memory.state},
          {"model_bytes", r.memory.model},
          {"workspace_bytes", r.memory.workspace},
          {"max_strain_last_second", figure(r.strain_last_second)},
          {"max_strain", figure(r.strain_last)},
          {"p99_strain", figure(r.strain_p99)},
          {"penetration_fraction_of_radius", figure(r.penetration)},
          {"self_intersections_max", r.self_intersections},
          {"on_sphere", r.on_sphere},
          {"quality", r.quality},
          {"substep_tries", r.tries}};
}

// One CSV field (RFC 4180): quoted when it holds a comma, a quote or a line break, as a
// skipped run's reason can.
std::string csv_field(const nlohmann::json& value) {
  const std::string text = value.is_string() ? value.get<std::string>() : value.dump();
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

// Checked before the first run, so hours of benchmark are not lost to a typo at the end.
void check_results_folder(const BenchOptions& o) {
  io::check_output_folder("--out", o.out);
  std::error_code ec;
  for (const char* name : kResultFiles) {
    const fs::path file = fs::path(o.out) / name;
    if (!fs::exists(fs::symlink_status(file, ec))) continue;
    if (!o.force)
      throw InputError("--out " + o.out, std::string("already holds ") + name +
                                             " of an earlier run; choose another folder or pass "
                                             "--force to replace it");
    io::check_output("--out", file.string());
  }
}

// Returns the problem, or "" when both files were written.
std::string write_results(const std::string& dir, const std::vector<Row>& rows) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) return dir + ": cannot create the folder: " + ec.message();
  nlohmann::json all = nlohmann::json::array();
  std::string csv;
  for (const Row& r : rows) {
    const nlohmann::json j = to_json(r);
    all.push_back(j);
    if (csv.empty()) {
      for (auto it = j.begin(); it != j.end(); ++it) csv += (csv.empty() ? "" : ",") + it.key();
      csv += "\n";
    }
    std::string line;
    for (auto it = j.begin(); it != j.end(); ++it)
      line += (line.empty() ? "" : ",") + csv_field(*it);
    csv += line + "\n";
  }
  try {
    io::write_output((fs::path(dir) / kResultFiles[0]).string(), json_text(all));
    io::write_output((fs::path(dir) / kResultFiles[1]).string(), csv);
  } catch (const io::OutputError& e) {
    return e.what();
  }
  return "";
}

int bench(BenchOptions o) {
  if (o.methods.empty())
    for (Method m : kAllMethods) o.methods.push_back(to_string(m));
  for (const std::string& name : o.methods) {
    if (!method_from_string(name)) {
      std::fprintf(stderr, "drape: error: --methods: unknown method \"%s\"; expected %s\n",
                   name.c_str(), method_names().c_str());
      return kExitBadInput;
    }
  }
  for (const std::string& p : o.precisions) {
    if (p != to_string(Precision::f64) && p != to_string(Precision::f32)) {
      std::fprintf(stderr,
                   "drape: error: --precision: unknown precision \"%s\"; expected %s or %s\n",
                   p.c_str(), to_string(Precision::f64), to_string(Precision::f32));
      return kExitBadInput;
    }
  }
  // auto chooses its precision itself: it runs once, whatever --precision lists.
  std::vector<Variant> variants;
  for (const std::string& m : o.methods) {
    if (m == to_string(Method::automatic)) {
      variants.push_back({m, to_string(Precision::f64)});
      continue;
    }
    for (const std::string& p : o.precisions)
      if (p == to_string(Precision::f64) || m == to_string(Method::xpbd))
        variants.push_back({m, p});
  }
  if (variants.empty()) {
    std::fprintf(stderr,
                 "drape: error: --precision: only xpbd runs in single precision; add double or "
                 "xpbd to --methods\n");
    return kExitBadInput;
  }
  const bool xpbd =
      std::find(o.methods.begin(), o.methods.end(), to_string(Method::xpbd)) != o.methods.end();
  if (!xpbd && !o.xpbd_options.empty()) {
    std::fprintf(stderr, "drape: error: %s: applies to xpbd runs only, and --methods has no xpbd\n",
                 o.xpbd_options.front().c_str());
    return kExitBadInput;
  }
  for (const std::string& s : o.scenes) {
    if (s != "hang" && s != "hang-lr" && s != "drape" && s != "drape-mesh" && s != "drape-sc" &&
        s != "pile") {
      std::fprintf(stderr,
                   "drape: error: --scenes: unknown scene \"%s\"; expected hang, hang-lr, "
                   "drape, drape-mesh, drape-sc or pile\n",
                   s.c_str());
      return kExitBadInput;
    }
  }
  try {
    check_results_folder(o);
  } catch (const InputError& e) {
    std::fprintf(stderr, "drape: error: %s\n", e.what());
    return kExitBadInput;
  }
  for (std::vector<int>* counts : {&o.stiff_sweeps, &o.line_passes}) {
    std::sort(counts->begin(), counts->end());
    counts->erase(std::unique(counts->begin(), counts->end()), counts->end());
  }
  install_interrupt_handlers();
  std::vector<Row> rows;
  const int64_t total =
      static_cast<int64_t>(o.scenes.size() * o.sizes.size() * variants.size() * o.threads.size());
  Progress bar("bench", total, true);
  for (const std::string& scene : o.scenes)
    for (int n : o.sizes)
      for (const Variant& v : variants) {
        Found found;
        for (int t : o.threads) {
          if (interrupt_signal()) break;
          bar.update(static_cast<int64_t>(rows.size()),
                     scene + "-" + std::to_string(n) + " " + v.method + " (" + v.precision + ") " +
                         std::to_string(t) + " thread(s)" +
                         (found.substeps == 0 && searchable(v.method) ? ", finding substeps" : ""));
          rows.push_back(bench_best(o, scene, n, v, t, found));
        }
      }
  bar.finish();
  print_table(rows);
  if (const std::string problem = write_results(o.out, rows); !problem.empty()) {
    std::fprintf(stderr, "drape: error: %s\n", problem.c_str());
    return kExitOutputFailed;
  }
  std::printf("results written to %s/bench.json and %s/bench.csv\n", o.out.c_str(), o.out.c_str());
  if (int s = interrupt_signal()) return interrupt_exit_code(s);
  return kExitOk;
}

}  // namespace

std::function<int()> add_bench_command(CLI::App& app) {
  auto o = std::make_shared<BenchOptions>();
  CLI::App* cmd = app.add_subcommand(
      "bench", "Time the standard scenes (bench/scenes) at several sizes, methods and threads");
  cmd->add_option(
         "--scenes", o->scenes,
         "Scenes: hang, hang-lr (long-range attachments), drape, drape-mesh (drape's cloth "
         "as an irregular triangle mesh of N x N vertices), drape-sc (drape with "
         "self-collision), pile (a cloth folding onto itself on the ground, "
         "self-collision on; its bar: no crossing triangles at any frame)")
      ->delimiter(',')
      ->capture_default_str();
  cmd->add_option("--sizes", o->sizes, "Grid sizes N (N×N particles)")
      ->delimiter(',')
      ->check(CLI::Range(2, 4096))
      ->capture_default_str();
  cmd->add_option("--methods", o->methods, "Methods (default: all)")->delimiter(',');
  cmd->add_option("--precision", o->precisions,
                  "Precisions: double, single (single runs xpbd only; auto chooses its own)")
      ->delimiter(',')
      ->capture_default_str();
  cmd->add_option("--threads", o->threads, "Thread counts")
      ->delimiter(',')
      ->check(CLI::Range(1, 256))
      ->capture_default_str();
  cmd->add_option("--frames", o->frames, "Frames per run")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  cmd->add_option("--max-updates", o->max_updates,
                  "Skip runs whose frames × substeps × (particles + springs) exceed this")
      ->check(finite_range(1.0, 1e18))
      ->capture_default_str();
  cmd->add_option("--out", o->out, "Folder for bench.json and bench.csv")
      ->check(kNonEmpty)
      ->capture_default_str();
  cmd->add_flag("--force", o->force, "Replace bench.json and bench.csv of an earlier run in --out");
  CLI::Option* sweeps =
      cmd->add_option("--stiff-sweeps", o->stiff_sweeps,
                      "xpbd: the solver.stiff_sweeps counts the search tries, each with its own "
                      "substep search; the cheapest run that meets the bar is reported")
          ->delimiter(',')
          ->check(CLI::Range(0, 10000))
          ->capture_default_str();
  CLI::Option* lines =
      cmd->add_option("--line-passes", o->line_passes,
                      "xpbd: the solver.line_passes counts the search tries too, each with 0, 1 "
                      "and 2 stiff sweeps after the passes and each with its own substep search "
                      "(0: none; not on hang, whose pins have no attachments)")
          ->delimiter(',')
          ->check(CLI::Range(0, 10000))
          ->capture_default_str();
  CLI::Option* no_search = cmd->add_flag("!--no-search", o->search,
                                         "xpbd: run at its automatic substeps instead of "
                                         "searching for the fewest that meet the quality bar");
  cmd->footer(exit_codes_help({kExitOk, kExitBadInput, kExitOutputFailed, 129, 130, 143}));
  return [cmd, o, sweeps, lines, no_search] {
    if (!cmd->parsed()) return -1;
    for (const CLI::Option* xpbd_only : {sweeps, lines, no_search})
      if (xpbd_only->count() > 0) o->xpbd_options.push_back(xpbd_only->get_name());
    return bench(*o);
  };
}

}  // namespace drape::app
