// The interactive viewer behind `drape view`: a GLFW window with an OpenGL 3.3 core context,
// the shared renderer, an orbit camera, the seed's mouse drag, and a Dear ImGui panel that edits
// the scene live.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "drape/scene.h"

namespace drape::app {

/// How `drape view` was asked to run.
struct ViewerOptions {
  std::string scene;              ///< scene file to open
  std::vector<std::string> sets;  ///< KEY=VALUE overrides applied to it
  int width = 1280;               ///< window size in screen units
  int height = 720;
  bool vsync = true;       ///< wait for the display between frames
  bool panel = true;       ///< show the ImGui panel
  int64_t frames = 0;      ///< > 0: run this many frames, then exit (scripted use)
  std::string screenshot;  ///< scripted: save the last frame here as PNG
  std::string report;      ///< scripted: write figures (and the drag's result) as JSON
  int threads = 0;         ///< the simulation's threads; 0: every core
  /// Scripted drag in window units: press at (x0, y0), move to (x1, y1) over the first half of
  /// the frames, hold until the end.
  std::optional<std::array<double, 4>> drag;
  bool carry = false;  ///< the scripted drag holds Shift: it carries the collider under it
};

/// Opens the window and runs until it is closed (or the scripted frames are done). Returns the
/// exit code; prints one line and returns kExitNoGraphics when no display or context can be had.
int run_viewer(const ViewerOptions& options, const SceneDef& scene);

}  // namespace drape::app
