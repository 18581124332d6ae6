// glTF 2.0 binary (.glb): the cloth's mesh (positions, normals, UVs, triangles), its motion as
// morph targets played by a weights animation, and the colliders as meshes, in one file that
// Blender and three.js import and play.
// Colliders that move (a motion, the viewer's hand) get a node animation of their translation
// and rotation at each frame's time, relative to where they stood at frame 0 (their mesh).
//
// Layout: frame 0 is the mesh; every later frame kept is a morph target holding its position and
// normal displacements from frame 0; one animation samples the weights at each frame's time with
// linear interpolation, target k's weight 1 at its own frame and 0 at the others, so playback
// moves from frame to frame along straight lines as the run's own frames would. The weights take
// keyframes × targets floats (4 MB at 1000 frames): export long runs with --every.
//
// Frames are streamed to an unnamed scratch file as they come, so memory stays that of one frame;
// finish() writes the .glb under a temporary name and renames it.
#pragma once

#include <array>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "drape/cloth.h"
#include "drape/collider.h"

namespace drape::io {

class GlbWriter {
 public:
  /// Starts `file` with the mesh and frame 0 (`first`, at `time` s). `name` names the cloth's
  /// node and mesh; `generator` goes in the asset's description. Throws OutputError
  /// naming the file if its scratch space cannot be had.
  GlbWriter(std::string file, std::string name, std::string generator, const ClothModel& model,
            const ClothState& first, double time, const std::vector<Collider>& colliders);
  ~GlbWriter();
  GlbWriter(const GlbWriter&) = delete;
  GlbWriter& operator=(const GlbWriter&) = delete;

  /// Adds frame number `frame` at `time` s, later than the previous frame's. Its morph target
  /// is named after it ("frame_00005", as the OBJ export names its file). `colliders`: where
  /// the colliders given at the start are now (empty: where they were at the last frame).
  void add_frame(const ClothState& state, int64_t frame, double time,
                 const std::vector<Collider>& colliders = {});

  /// Writes the file (as io::OutputFile writes: whole or not at all). Throws OutputError naming the file
  /// if it cannot be written, or if it would pass the format's 4 GiB.
  void finish();

  int64_t frames() const { return static_cast<int64_t>(times_.size()); }

  /// About how many bytes a file of `frames` frames of this cloth takes; callers check it
  /// against kMaxBytes before a long run rather than fail at its end.
  static double estimated_bytes(int64_t particles, int64_t triangles, int64_t frames);
  static constexpr double kMaxBytes = 4294967295.0;  ///< a .glb's length is a uint32

 private:
  std::string file_, name_, generator_;
  std::vector<Vec3> x0_;          // frame 0, m
  std::vector<float> position0_;  // frame 0 as stored: x, y, z per vertex
  std::vector<float> normal0_;    // frame 0's unit normals as stored
  std::vector<float> uv_;         // u, v per vertex (v down, as glTF has it)
  std::vector<uint32_t> indices_;
  std::vector<std::array<float, 6>> target_bounds_;  // min x, y, z, max x, y, z of each target
  std::vector<float> times_;                         // s, every frame's
  std::vector<std::string> target_names_;
  std::vector<float> delta_;  // one frame's displacements, reused
  std::vector<Collider> colliders_;
  // Per frame and collider, its node's transform from frame 0: translation x, y, z, then the
  // rotation as a unit quaternion x, y, z, w (glTF's order).
  std::vector<std::array<float, 7>> tracks_;
  Vec3 focus_;               // where the cloth starts: planes are drawn around it
  double extent_;            // m, the side of a plane's square
  FILE* scratch_ = nullptr;  // the morph targets, frame after frame
};

}  // namespace drape::io
