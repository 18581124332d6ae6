// `drape lab`: the textile lab's tests on a material, simulated. `lab cantilever` is Peirce's
// bending-length test (ASTM D1388), `lab cusick` the drape-coefficient test (ISO 9073-9); both
// print what a lab would report beside what the material's numbers predict, or JSON.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "app/commands.h"
#include "app/options.h"
#include "app/terminal.h"
#include "drape/error.h"
#include "io/output_file.h"
#include "io/scene_io.h"
#include "io/shown_text.h"
#include "lab/cantilever.h"
#include "lab/cusick.h"
#ifdef DRAPE_HAVE_RENDER
#include "render/renderer.h"
#endif

namespace drape::app {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

struct LabOptions {
  std::string material;
  std::vector<std::string> sets;
  int resolution = 0;  // 0: the test's default
  bool weft = false;
  double seconds = 10.0;
  std::string picture;
  bool no_picture = false;
  bool json = false;
  bool quiet = false;
  bool force = false;
  int threads = 0;
};

// --material NAME|FILE: a preset's name, or a JSON file holding a material as cloth.material
// does. Returns it as cloth.material will hold it; `label` names it for the report.
MaterialDef read_material_option(const std::string& arg, std::string& label) {
  std::error_code ec;
  const bool file = fs::exists(arg, ec) || arg.find('/') != std::string::npos ||
                    fs::path(arg).extension() == ".json";
  if (!file) {
    label = arg;
    return io::read_material(json(arg), "--material");
  }
  const json j = io::load_scene_json(arg);  // names the file in its errors
  try {
    MaterialDef m = io::read_material(j, "");
    // Its ranges, checked as a scene's cloth.material is, named as keys of the file.
    SceneDef alone;
    alone.cloth.material = m;
    try {
      check(alone);
    } catch (const InputError& e) {
      const std::string prefix = "cloth.material.";
      throw InputError(e.path().starts_with(prefix) ? e.path().substr(prefix.size()) : e.path(),
                       e.problem());
    }
    label = m.name.empty() ? fs::path(arg).filename().string() : m.name;
    return m;
  } catch (const InputError& e) {
    throw InputError(e.path().empty() ? arg : arg + ": " + e.path(), e.problem());
  }
}

// The test's scene with the user's overrides, read as any scene is.
SceneDef lab_scene(json scene, const LabOptions& o, const std::string& source) {
  for (const std::string& s : o.sets) {
    try {
      io::apply_override(scene, s);
    } catch (const InputError& e) {
      throw InputError(source + ": --set " + s + ": " + e.path(), e.problem());
    }
  }
  return io::parse_scene(scene, source);
}

double centimetres(double m) {
  return 100.0 * m;
}

template <class Result>
int report_failure(const std::string& test, const Result& r) {
  if (r.stopped) {
    const int signal = interrupt_signal();
    std::fprintf(stderr, "drape: lab %s interrupted; nothing measured\n", test.c_str());
    return interrupt_exit_code(signal ? signal : 2);
  }
  if (r.diverged) {
    std::fprintf(stderr, "drape: lab %s: the simulation diverged at frame %lld: %s\n", test.c_str(),
                 static_cast<long long>(r.diverged_frame), r.message.c_str());
    return kExitDiverged;
  }
  return kExitOk;
}

int cantilever(const LabOptions& o) {
  use_threads(o.threads);
  const auto t0 = std::chrono::steady_clock::now();
  SceneDef def;
  std::string label;
  const int cells = o.resolution > 0 ? o.resolution : 80;
  try {
    MaterialDef m = read_material_option(o.material, label);
    if (o.weft) {
      // A weft strip: the same test with the material's warp and weft exchanged.
      std::swap(m.stretch.x(), m.stretch.y());
      std::swap(m.bending.x(), m.bending.y());
    }
    def = lab_scene(lab::cantilever_scene(io::material_json(m), cells), o, "lab cantilever");
  } catch (const InputError& e) {
    std::fprintf(stderr, "drape: error: %s\n", e.what());
    return kExitBadInput;
  }
  install_interrupt_handlers();
  Progress bar("cantilever " + io::shown(label, 30), def.cloth.cols, !o.quiet && !o.json);
  lab::CantileverResult r;
  try {
    r = lab::run_cantilever(
        def,
        [&](const lab::CantileverStage& s, int left) {
          char detail[96];
          std::snprintf(detail, sizeof detail, "overhang %.2f cm, tip %.1f° below the edge",
                        centimetres(s.overhang), s.angle);
          bar.update(def.cloth.cols - left, detail);
        },
        interrupt_flag());
  } catch (const InputError& e) {
    bar.finish();
    std::fprintf(stderr, "drape: error: lab cantilever: %s\n", e.what());
    return kExitBadInput;
  }
  bar.finish();
  if (r.stopped || r.diverged) return report_failure("cantilever", r);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  int frames = 0;
  for (const lab::CantileverStage& s : r.stages) frames += s.frames;
  const char* direction = o.weft ? "weft" : "warp";
  if (o.json) {
    json stages = json::array();
    for (const lab::CantileverStage& s : r.stages)
      stages.push_back({{"overhang_m", s.overhang},
                        {"angle_deg", s.angle},
                        {"frames", s.frames},
                        {"at_rest", s.at_rest}});
    const json out = {{"test", "cantilever"},
                      {"material", label},
                      {"direction", direction},
                      {"cells", cells},
                      {"method", io::to_json(def)["solver"]["method"]},
                      {"reached", r.reached},
                      {"overhang_m", r.reached ? json(r.overhang) : json(nullptr)},
                      {"bending_length_m", r.reached ? json(r.bending_length) : json(nullptr)},
                      {"rigidity_Nm", r.reached ? json(r.rigidity) : json(nullptr)},
                      {"material_bending_length_m", r.material_bending_length},
                      {"material_rigidity_Nm", r.material_rigidity},
                      {"elastica_overhang_m", r.elastica_overhang},
                      {"note", r.message},
                      {"stages", stages},
                      {"frames", frames},
                      {"wall_seconds", seconds}};
    std::printf("%s\n", out.dump(2).c_str());
    return kExitOk;
  }
  std::printf(
      "cantilever test (ASTM D1388) of %s along the %s: a %g × %g cm strip of %d cells, "
      "%s\n",
      io::shown(label).c_str(), direction, centimetres(def.cloth.width),
      centimetres(def.cloth.height), cells,
      io::to_json(def)["solver"]["method"].get<std::string>().c_str());
  if (!r.reached) {
    std::printf(
        "  the tip did not reach the 41.5° plane before the strip ran out (at %.2f cm "
        "overhang it was %.1f° below the edge): the bending length is over %.2f cm\n",
        centimetres(r.stages.back().overhang), r.stages.back().angle,
        centimetres(0.5 * r.stages.back().overhang));
  } else {
    std::printf("  overhang         %7.2f cm     exact elastica of the material: %.2f cm\n",
                centimetres(r.overhang), centimetres(r.elastica_overhang));
    std::printf("  bending length   %7.2f cm     the material's (B/(ρg))^(1/3):   %.2f cm\n",
                centimetres(r.bending_length), centimetres(r.material_bending_length));
    std::printf("  rigidity ρg·c³   %7.2f µN·m   the material's B:                %.2f µN·m\n",
                1e6 * r.rigidity, 1e6 * r.material_rigidity);
  }
  if (!r.message.empty()) std::printf("  note: %s\n", r.message.c_str());
  int resting = 0;
  for (const lab::CantileverStage& s : r.stages) resting += s.at_rest;
  std::printf("  %zu overhangs (%d came to rest), %d frames, %.1f s\n", r.stages.size(), resting,
              frames, seconds);
  return kExitOk;
}

int cusick(const LabOptions& o) {
  use_threads(o.threads);
  const auto t0 = std::chrono::steady_clock::now();
  SceneDef def;
  std::string label, picture;
  const int rings = o.resolution > 0 ? o.resolution : lab::kCusickRings;
  try {
    const MaterialDef m = read_material_option(o.material, label);
    def = lab_scene(lab::cusick_scene(io::material_json(m)), o, "lab cusick");
    lab::use_cusick_specimen(def, rings);
    if (!o.no_picture) {
      picture = o.picture.empty() ? "cusick-" + io::shown(label) + ".png" : o.picture;
#ifndef DRAPE_HAVE_RENDER
      if (!o.picture.empty())
        throw InputError("--picture " + o.picture,
                         "this drape was built without stb, which writes PNG pictures");
      picture.clear();
#endif
      std::error_code ec;
      if (!picture.empty() && fs::exists(picture, ec) && !o.force)
        throw InputError("--picture " + picture, "already exists; pass --force to replace it");
      if (!picture.empty()) io::check_output("--picture", picture);
    }
  } catch (const InputError& e) {
    std::fprintf(stderr, "drape: error: %s\n", e.what());
    return kExitBadInput;
  }
  install_interrupt_handlers();
  Progress bar("cusick " + io::shown(label, 30), std::lround(o.seconds / def.solver.dt),
               !o.quiet && !o.json);
  lab::CusickResult r;
  try {
    r = lab::run_cusick(
        def, o.seconds,
        [&](int frame, int) {
          char detail[64];
          std::snprintf(detail, sizeof detail, "%.2f s draped", frame * def.solver.dt);
          bar.update(frame, detail);
        },
        interrupt_flag());
  } catch (const InputError& e) {
    bar.finish();
    std::fprintf(stderr, "drape: error: lab cusick: %s\n", e.what());
    return kExitBadInput;
  }
  bar.finish();
  if (r.stopped || r.diverged) return report_failure("cusick", r);
  std::string picture_error;
#ifdef DRAPE_HAVE_RENDER
  if (!picture.empty()) {
    try {
      const int size = r.measure.shadow.size;
      render::write_png(picture, size, size, lab::shadow_picture(r.measure));
    } catch (const io::OutputError& e) {
      picture_error = e.what();
    }
  }
#endif
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const lab::CusickMeasure& m = r.measure;
  const double pi = 3.14159265358979323846;
  if (o.json) {
    const json out = {
        {"test", "cusick"},
        {"material", label},
        {"rings", rings},
        {"particles", def.cloth.mesh->positions.size()},
        {"method", io::to_json(def)["solver"]["method"]},
        {"drape_coefficient_percent", m.drape_coefficient},
        {"folds", m.folds},
        {"shadow_area_m2", m.area},
        {"pedestal_area_m2", pi * lab::kPedestalRadius * lab::kPedestalRadius},
        {"specimen_area_m2", pi * lab::kSpecimenRadius * lab::kSpecimenRadius},
        {"hem_radius_m", m.hem},
        {"at_rest", r.at_rest},
        {"seconds_draped", r.frames * def.solver.dt},
        {"picture", picture.empty() || !picture_error.empty() ? json(nullptr) : json(picture)},
        {"wall_seconds", seconds}};
    std::printf("%s\n", out.dump(2).c_str());
  } else {
    std::printf(
        "cusick drape test (ISO 9073-9) of %s: a 30 cm disc (%d rings, %zu particles) on "
        "an 18 cm pedestal, %s\n",
        io::shown(label).c_str(), rings, def.cloth.mesh->positions.size(),
        io::to_json(def)["solver"]["method"].get<std::string>().c_str());
    std::printf("  drape coefficient %5.1f %%\n", m.drape_coefficient);
    std::printf("  folds             %5d\n", m.folds);
    std::printf("  shadow            %.4f m² (the pedestal %.4f, the flat specimen %.4f)\n", m.area,
                pi * lab::kPedestalRadius * lab::kPedestalRadius,
                pi * lab::kSpecimenRadius * lab::kSpecimenRadius);
    std::printf("  %s after %.2f s draped; %.1f s\n",
                r.at_rest ? "at rest" : "NOT at rest (raise --seconds)", r.frames * def.solver.dt,
                seconds);
    if (!picture.empty() && picture_error.empty())
      std::printf("  top view written to %s\n", picture.c_str());
  }
  if (!picture_error.empty()) {
    std::fprintf(stderr, "drape: error: %s\n", picture_error.c_str());
    return kExitOutputFailed;
  }
  return kExitOk;
}

void add_common(CLI::App* cmd, LabOptions& o, const std::string& resolution_help) {
  cmd->add_option("--material", o.material,
                  "A preset's name (denim, knit, polyester, cotton-polyester) or a JSON file "
                  "holding a material as cloth.material does")
      ->required()
      ->check(kNonEmpty);
  cmd->add_option("--resolution", o.resolution, resolution_help)->check(CLI::Range(4, 1024));
  cmd->add_option("--set", o.sets, "Override a key of the test's scene: KEY=VALUE")
      ->take_all()
      ->allow_extra_args(false);
  cmd->add_flag("--json", o.json, "Print the results as JSON");
  cmd->add_flag("--quiet", o.quiet, "No progress bar");
  add_threads_option(cmd, o.threads);
}

}  // namespace

std::function<int()> add_lab_command(CLI::App& app) {
  auto o = std::make_shared<LabOptions>();
  CLI::App* lab = app.add_subcommand(
      "lab", "A textile lab's tests of a material, simulated: cantilever, cusick");
  lab->require_subcommand(1);
  CLI::App* cant = lab->add_subcommand(
      "cantilever",
      "Peirce's cantilever (ASTM D1388): the bending length and rigidity of a strip sliding "
      "over an edge until its tip meets a plane 41.5° below");
  add_common(cant, *o, "Cells along the 20 cm strip (default 80)");
  cant->add_flag("--weft", o->weft, "Cut the strip along the weft instead of the warp");
  CLI::App* cus = lab->add_subcommand(
      "cusick",
      "The Cusick drape test (ISO 9073-9): a 30 cm disc on an 18 cm pedestal; the drape "
      "coefficient, the folds and a top view");
  add_common(cus, *o,
             "Rings of the disc's mesh across its radius (default " +
                 std::to_string(lab::kCusickRings) + ")");
  cus->add_option("--seconds", o->seconds, "Drape at most this long before measuring (s)")
      ->check(finite_range(0.1, 600.0))
      ->capture_default_str();
  cus->add_option("--picture", o->picture,
                  "Write the top view (the shadow) to this PNG (default: cusick-MATERIAL.png)")
      ->check(kNonEmpty);
  cus->add_flag("--no-picture", o->no_picture, "Write no picture");
  cus->add_flag("--force", o->force, "Replace --picture if it exists");
  for (CLI::App* c : {cant, cus})
    c->footer(exit_codes_help({kExitOk, kExitBadInput, kExitDiverged, kExitOutputFailed, 130}));
  return [cant, cus, o] {
    if (cant->parsed()) return cantilever(*o);
    if (cus->parsed()) return cusick(*o);
    return -1;
  };
}

}  // namespace drape::app
