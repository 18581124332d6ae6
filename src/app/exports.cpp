#include "app/exports.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>

#include "app/frame_folder.h"
#include "drape/error.h"
#include "io/mesh_export.h"
#include "io/output_file.h"

namespace drape::app {

namespace fs = std::filesystem;

const char* to_string(ExportFormat f) {
  switch (f) {
    case ExportFormat::obj:
      return "obj";
    case ExportFormat::ply:
      return "ply";
    case ExportFormat::pc2:
      return "pc2";
    case ExportFormat::glb:
      return "glb";
  }
  return "?";
}

namespace {

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

bool is_cache(ExportFormat f) {
  return f == ExportFormat::pc2 || f == ExportFormat::glb;
}

const std::vector<std::string> kFrameExtensions{"obj", "ply"};

std::string option_of(const ExportTarget& t) {
  return "--export " + (t.dir.empty() ? t.file : t.dir);
}

}  // namespace

ExportTarget resolve_export(const std::string& path, const std::string& format,
                            const std::string& scene, int every) {
  ExportTarget t;
  t.every = every;
  const std::string ext = lower(fs::path(path).extension().string());
  const bool cache_file = ext == ".pc2" || ext == ".glb";
  if (cache_file) {
    t.format = ext == ".pc2" ? ExportFormat::pc2 : ExportFormat::glb;
    if (!format.empty() && format != to_string(t.format))
      throw InputError("--format " + format, "does not match --export " + path +
                                                 ", whose name ends in " + ext +
                                                 "; give one or the other");
    t.file = path;
  } else {
    t.format = format == "ply"   ? ExportFormat::ply
               : format == "pc2" ? ExportFormat::pc2
               : format == "glb" ? ExportFormat::glb
                                 : ExportFormat::obj;
    t.dir = path;
    if (is_cache(t.format))
      t.file =
          (fs::path(path) / (fs::path(scene).stem().string() + "." + to_string(t.format))).string();
  }
  if (t.format == ExportFormat::pc2)
    t.rest_mesh = fs::path(t.file).replace_extension(".obj").string();
  return t;
}

void check_export(const ExportTarget& t, const Simulation& sim, int64_t frames, bool force) {
  const std::string option = option_of(t);
  if (!is_cache(t.format)) {
    check_frame_folder("--export", t.dir, kFrameExtensions, force);
    return;
  }
  std::error_code ec;
  // A cache named into a folder (--export FOLDER --format pc2) gets the folder made, as frames do.
  if (!t.dir.empty()) io::check_output_folder("--export", t.dir);
  for (const std::string& f : {t.file, t.rest_mesh}) {
    if (f.empty()) continue;
    if (t.dir.empty() || fs::exists(t.dir, ec)) io::check_output("--export", f);
    if (fs::exists(f, ec) && !force)
      throw InputError(option, f + " already exists; choose another name or pass --force to "
                                   "overwrite it");
  }
  if (t.format == ExportFormat::glb) {
    const int64_t kept = frames / t.every + 2;
    const double bytes = io::GlbWriter::estimated_bytes(
        sim.model().size(), static_cast<int64_t>(sim.model().triangles.size()), kept);
    if (bytes > io::GlbWriter::kMaxBytes) {
      char problem[200];
      std::snprintf(problem, sizeof problem,
                    "%lld frames of %d particles would take about %.1f GiB, more than the 4 GiB "
                    "a .glb can hold; keep fewer frames with --every",
                    static_cast<long long>(kept), sim.model().size(), bytes / (1 << 30));
      throw InputError(option, problem);
    }
  }
}

int64_t prepare_export(const ExportTarget& t) {
  if (!is_cache(t.format)) return prepare_frame_folder("--export", t.dir, kFrameExtensions);
  std::error_code ec;
  if (!t.dir.empty() && !fs::create_directories(t.dir, ec) && ec)
    throw InputError("--export " + t.dir, "cannot create the folder: " + ec.message());
  return 0;
}

Exporter::Exporter(ExportTarget target, int64_t frames, std::string generator)
    : target_(std::move(target)), frames_(frames), generator_(std::move(generator)) {}

Exporter::~Exporter() = default;

void Exporter::after_frame(const Simulation& sim) {
  const int64_t f = sim.frame();
  const bool on_step = f % target_.every == 0;
  // A PC2 cache samples evenly, so it cannot hold a last frame off its step.
  const bool last = f == frames_ && target_.format != ExportFormat::pc2;
  if (on_step || last) write(sim);
}

void Exporter::finish(const Simulation& sim, const RunResult& run) {
  if (run.status == RunStatus::interrupted && last_written_ != sim.frame() &&
      target_.format != ExportFormat::pc2)
    write(sim);
  if (pc2_) pc2_->finish();
  if (glb_) glb_->finish();
}

void Exporter::write(const Simulation& sim) {
  const ClothModel& model = sim.model();
  const ClothState& state = sim.state();
  switch (target_.format) {
    case ExportFormat::obj:
    case ExportFormat::ply:
      io::write_mesh(
          app::frame_file(target_.dir, sim.frame(), to_string(target_.format)),
          target_.format == ExportFormat::obj ? io::MeshFormat::obj : io::MeshFormat::ply, model,
          state);
      break;
    case ExportFormat::pc2:
      if (!pc2_) {
        io::write_mesh(target_.rest_mesh, io::MeshFormat::obj, model, state);
        pc2_ = std::make_unique<io::Pc2Writer>(target_.file, model.size(),
                                               static_cast<float>(sim.frame()),
                                               static_cast<float>(target_.every));
      }
      pc2_->add_frame(state.x);
      break;
    case ExportFormat::glb:
      if (!glb_)
        glb_ = std::make_unique<io::GlbWriter>(target_.file, sim.def().name, generator_, model,
                                               state, sim.time(), sim.colliders());
      else
        glb_->add_frame(state, sim.frame(), sim.time(), sim.colliders());
      break;
  }
  ++written_;
  last_written_ = sim.frame();
}

std::string Exporter::summary() const {
  const std::string n = std::to_string(written_);
  switch (target_.format) {
    case ExportFormat::obj:
    case ExportFormat::ply:
      return n + " " + to_string(target_.format) + " files to " + target_.dir;
    case ExportFormat::pc2:
      return n + " frames to " + target_.file + " (rest mesh " + target_.rest_mesh + ")";
    case ExportFormat::glb:
      return n + " frames to " + target_.file;
  }
  return "";
}

}  // namespace drape::app
