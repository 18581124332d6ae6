// Fuzzes the scene loader: any bytes are either a scene or an InputError, never a crash, hang,
// leak or undefined behaviour. Small valid scenes are also built and stepped, so the checks
// that guard the solver are fuzzed too.
#include <cstddef>
#include <cstdint>
#include <string>

#include "drape/error.h"
#include "drape/simulation.h"
#include "io/scene_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception&) {
    return 0;  // not JSON: the loader reports that itself (tested elsewhere)
  }
  try {
    drape::SceneDef def = drape::io::parse_scene(j, "fuzz.json");
    // Only small, cheap runs: the budget is the command line's job.
    if (int64_t{def.cloth.cols} * def.cloth.rows > 4096) return 0;
    def.solver.max_substeps = std::min(def.solver.max_substeps, 200);
    if (def.solver.substeps > 200) return 0;
    drape::Simulation sim(def);
    for (int f = 0; f < 3 && sim.step(); ++f) {
    }
    (void)sim.diagnostics();
  } catch (const drape::InputError&) {
  }
  return 0;
}
