// `drape mesh SHAPE --out FILE.obj`: writes one of the cloth shapes made in code (shapes in
// drape/mesh.h) as an OBJ file; scripts/meshes.sh makes the shipped meshes/ with it.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <string>

#include "app/commands.h"
#include "drape/error.h"
#include "drape/mesh.h"
#include "io/mesh_export.h"

namespace drape::app {

namespace {

struct MeshOptions {
  std::string shape;
  std::string out;
  int resolution = 32;
  bool force = false;
};

// The shapes at the sizes the shipped scenes use them, about `n` vertices across.
ClothMesh make(const std::string& shape, int n, std::string& description) {
  char text[160];
  if (shape == "disc") {
    const int rings = std::max(1, n / 2);
    std::snprintf(text, sizeof text, "a round tablecloth 1.5 m across, %d rings, irregular", rings);
    description = text;
    return shapes::disc(0.75, rings);
  }
  if (shape == "tube") {
    const double radius = 0.25, height = 0.6;
    const int down =
        std::max(2, static_cast<int>(std::lround(height / (2 * std::numbers::pi * radius / n))) + 1);
    std::snprintf(text, sizeof text, "a skirt: an open tube of radius %.2f m, %.2f m long, %d x %d",
                  radius, height, n, down);
    description = text;
    return shapes::tube(radius, height, n, down);
  }
  if (shape == "flag") {
    const double width = 1.5, height = 1.0;
    const int rows = std::max(2, static_cast<int>(std::lround(n * height / width)));
    std::snprintf(text, sizeof text,
                  "a swallowtail flag %.1f x %.1f m, pole edge at x = 0, %d x %d", width, height, n,
                  rows);
    description = text;
    return shapes::flag(width, height, 0.35, n, rows);
  }
  if (shape == "jittered") {
    std::snprintf(text, sizeof text, "a 2 m square, %d x %d vertices jittered, diagonals at random",
                  n, n);
    description = text;
    return shapes::jittered_grid(2.0, n);
  }
  throw InputError("SHAPE", "unknown shape \"" + shape +
                                "\"; expected disc, tube, flag or jittered");
}

int mesh(const MeshOptions& o) {
  try {
    std::error_code ec;
    if (std::filesystem::exists(o.out, ec) && !o.force)
      throw InputError("--out " + o.out, "already exists; pass --force to replace it");
    std::string description;
    const ClothMesh m = make(o.shape, o.resolution, description);
    io::write_obj(o.out, m, "drape mesh " + o.shape + " --resolution " +
                                std::to_string(o.resolution) + ": " + description);
    std::printf("%s: %s; %zu vertices, %zu triangles\n", o.out.c_str(), description.c_str(),
                m.positions.size(), m.triangles.size());
    return kExitOk;
  } catch (const InputError& e) {
    std::fprintf(stderr, "drape: error: %s\n", e.what());
    return kExitBadInput;
  } catch (const std::exception& e) {  // the file could not be written
    std::fprintf(stderr, "drape: error: %s\n", e.what());
    return kExitBadInput;
  }
}

}  // namespace

std::function<int()> add_mesh_command(CLI::App& app) {
  auto o = std::make_shared<MeshOptions>();
  CLI::App* cmd = app.add_subcommand(
      "mesh", "Write a cloth shape made in code as an OBJ file (how meshes/ is made)");
  cmd->add_option("shape", o->shape, "disc, tube, flag or jittered")->required();
  cmd->add_option("--out", o->out, "The OBJ file to write")->required();
  cmd->add_option("--resolution", o->resolution, "About this many vertices across")
      ->check(CLI::Range(4, 2048))
      ->capture_default_str();
  cmd->add_flag("--force", o->force, "Replace --out if it exists");
  return [cmd, o] { return cmd->parsed() ? mesh(*o) : -1; };
}

}  // namespace drape::app
