#include "app/runner.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "app/commands.h"
#include "app/terminal.h"
#include "app/thread_chooser.h"
#include "drape/error.h"
#include "io/output_file.h"

namespace drape::app {

RunResult run_frames(Simulation& sim, int64_t frames, const RunHooks& hooks) {
  using clock = std::chrono::steady_clock;
  RunResult r;
  r.frame_ms.reserve(static_cast<size_t>(std::min<int64_t>(frames, 1 << 20)));
  Progress bar(hooks.progress_label, frames, !hooks.progress_label.empty());
  const auto start = clock::now();
  // False when an output failed: there is no point simulating what cannot be kept.
  auto after_frame = [&] {
    if (!hooks.after_frame) return true;
    try {
      hooks.after_frame(sim);
      return true;
    } catch (const io::OutputError& e) {
      r.status = RunStatus::output_failed;
      r.output_error = e.what();
      return false;
    }
  };
  const bool started = after_frame();
  // A signal stops the frame under way at its next substep (a 256×256 symplectic frame takes
  // seconds): the part done is kept, but neither timed nor counted.
  sim.set_stop_flag(interrupt_flag());
  ThreadChooser threads(hooks.threads);
  for (int64_t f = 0; started && f < frames; ++f) {
    threads.before_frame();
    const auto t0 = clock::now();
    const bool ok = sim.step();
    threads.after_frame(std::chrono::duration<double, std::milli>(clock::now() - t0).count());
    if (sim.stopped()) {
      r.status = RunStatus::interrupted;
      r.signal = interrupt_signal();
      break;
    }
    r.frame_ms.push_back(std::chrono::duration<double, std::milli>(clock::now() - t0).count());
    ++r.frames;
    if (!ok) {
      r.status = RunStatus::diverged;
      break;
    }
    if (!after_frame()) break;
    if (int s = interrupt_signal()) {
      r.status = RunStatus::interrupted;
      r.signal = s;
      break;
    }
    if (!hooks.progress_label.empty()) {
      char detail[96];
      const double elapsed = std::chrono::duration<double>(clock::now() - start).count();
      std::snprintf(detail, sizeof detail, "%lld/%lld frames  %.2f s sim  %.1f frames/s",
                    static_cast<long long>(f + 1), static_cast<long long>(frames), sim.time(),
                    elapsed > 0 ? (f + 1) / elapsed : 0.0);
      bar.update(f + 1, detail);
    }
  }
  bar.finish();
  r.wall_seconds = std::chrono::duration<double>(clock::now() - start).count();
  return r;
}

void check_memory(const SceneDef& def, const Budget& budget) {
  const int64_t particles = particle_count(def.cloth);
  const int64_t bytes = estimated_memory(def);
  if (bytes <= budget.bytes) return;
  const bool mesh = def.cloth.mesh != nullptr;
  char problem[320];
  std::snprintf(problem, sizeof problem,
                "%s%lld particles, about %.1f GiB, more than the %.1f GiB budget; %s, or pass "
                "--force to run it anyway",
                mesh ? "the mesh has "
                     : (std::to_string(def.cloth.cols) + "x" + std::to_string(def.cloth.rows) +
                        " is ")
                           .c_str(),
                static_cast<long long>(particles), static_cast<double>(bytes) / (1 << 30),
                static_cast<double>(budget.bytes) / (1 << 30),
                mesh ? "use a coarser mesh" : "lower the resolution");
  throw InputError(mesh ? "cloth.mesh" : "cloth.resolution", problem);
}

void check_memory(const SceneDef& def, int64_t picture_bytes, const std::string& option,
                  const Budget& budget) {
  check_memory(def, budget);
  const int64_t cloth = estimated_memory(def);
  if (cloth + picture_bytes <= budget.bytes) return;
  char problem[256];
  std::snprintf(problem, sizeof problem,
                "drawing at this size takes about %.1f GiB, which with the cloth's %.1f GiB is "
                "more than the %.1f GiB budget; choose a smaller size, or pass --force to draw "
                "it anyway",
                static_cast<double>(picture_bytes) / (1 << 30),
                static_cast<double>(cloth) / (1 << 30),
                static_cast<double>(budget.bytes) / (1 << 30));
  throw InputError(option, problem);
}

void check_work(const Simulation& sim, int64_t frames, const Budget& budget) {
  const double updates = static_cast<double>(frames) * sim.substeps_per_frame() *
                         static_cast<double>(sim.model().size() + sim.model().springs.size());
  if (updates <= budget.updates) return;
  char problem[320];
  std::snprintf(problem, sizeof problem,
                "%lld frames of %d substeps over %d particles and %zu springs is %.3g updates, "
                "hours of work (the budget is %.3g); shorten the duration, raise solver.dt, "
                "or pass --force to run it anyway",
                static_cast<long long>(frames), sim.substeps_per_frame(), sim.model().size(),
                sim.model().springs.size(), updates, budget.updates);
  throw InputError("duration", problem);
}

std::string method_text(const Simulation& sim) {
  const AutoChoice* a = sim.auto_choice();
  if (!a) return to_string(sim.def().solver.method);
  char text[200];
  std::snprintf(text, sizeof text,
                "auto: %s %s, %d substeps, %d line passes, %d stiff sweeps; effort raised %d, "
                "lowered %d times",
                to_string(a->method), to_string(a->precision), a->substeps, a->line_passes,
                a->stiff_sweeps, a->raises, a->lowers);
  std::string out = text;
  if (a->out_of_reach)
    out += " (the strain stays above solver.tolerance however hard it works: the springs' own "
           "stretch; stiffer springs or cloth.long_range would lower it)";
  return out;
}

int exit_code(const std::string& scene, const Simulation& sim, const RunResult& run,
              const char* kept) {
  if (sim.diverged()) {
    std::fprintf(stderr, "drape: error: %s: diverged at frame %lld (t = %.4g s): %s\n",
                 scene.c_str(), static_cast<long long>(sim.diverged_frame()), sim.time(),
                 sim.divergence().c_str());
    return kExitDiverged;
  }
  if (run.status == RunStatus::interrupted) {
    std::fprintf(stderr, "drape: interrupted at frame %lld; %s\n",
                 static_cast<long long>(sim.frame()), kept);
    return interrupt_exit_code(run.signal);
  }
  if (run.status == RunStatus::output_failed) {
    std::fprintf(stderr, "drape: error: %s; the run stopped at frame %lld\n",
                 run.output_error.c_str(), static_cast<long long>(sim.frame()));
    return kExitOutputFailed;
  }
  return kExitOk;
}

}  // namespace drape::app
