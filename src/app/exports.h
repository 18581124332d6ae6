// What `drape run --export` writes: one mesh file per kept frame (OBJ, PLY) into a folder, or
// one animation cache for the whole run (a PC2 point cache with its rest mesh, or a glTF
// binary), every --every frames.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "app/runner.h"
#include "drape/simulation.h"
#include "io/glb_writer.h"
#include "io/pc2_writer.h"

namespace drape::app {

enum class ExportFormat { obj, ply, pc2, glb };
const char* to_string(ExportFormat f);

struct ExportTarget {
  ExportFormat format = ExportFormat::obj;
  std::string dir;        ///< obj, ply: the folder of frame files
  std::string file;       ///< pc2, glb: the cache
  std::string rest_mesh;  ///< pc2: the OBJ beside it, frame 0 with the cache's vertex order
  int every = 1;          ///< keep every Nth frame
};

/// Resolves --export PATH and --format NAME (empty: from PATH). A PATH ending in .pc2 or .glb is
/// that cache; any other PATH is a folder, which gets frame_NNNNN.obj/.ply files, or SCENE.pc2 or
/// SCENE.glb named after the scene file `scene`. Throws InputError when --format contradicts
/// the file's extension.
ExportTarget resolve_export(const std::string& path, const std::string& format,
                            const std::string& scene, int every);

/// Before the run, changing nothing: that every file can be written (io::check_output,
/// check_frame_folder), that no earlier run's output would be overwritten unless `force` (frame
/// files in the folder, or the cache and its rest mesh), and that a .glb stays within the
/// format's 4 GiB. Throws InputError.
void check_export(const ExportTarget& target, const Simulation& sim, int64_t frames, bool force);

/// Then, once the run will go ahead: makes the frame folder and removes an earlier run's frames
/// from it (check_export let them through only with --force). Returns how many were removed.
int64_t prepare_export(const ExportTarget& target);

/// Writes one run's frames as they come.
class Exporter {
 public:
  /// `frames`: the frames the run will take if nothing stops it (the last is always kept where
  /// the format can place it). `generator` names drape's version in files that record it.
  Exporter(ExportTarget target, int64_t frames, std::string generator);
  ~Exporter();

  /// Called with frame 0 and after every frame; writes the frame if it is one to keep.
  void after_frame(const Simulation& sim);
  /// After the loop. A run stopped early by a signal keeps the frame it stopped at, where the
  /// format can place it (a PC2 cache's frames are evenly spaced, so only frames on its step go
  /// in); caches are completed and renamed to their names. A diverged frame is never written.
  void finish(const Simulation& sim, const RunResult& run);

  /// What was written, for the summary: "13 obj files to out".
  std::string summary() const;

 private:
  void write(const Simulation& sim);

  ExportTarget target_;
  int64_t frames_;
  std::string generator_;
  int64_t written_ = 0;
  int64_t last_written_ = -1;
  std::unique_ptr<io::Pc2Writer> pc2_;
  std::unique_ptr<io::GlbWriter> glb_;
};

}  // namespace drape::app
