// Draws a simulation with OpenGL 3.3 core: the cloth as a lit, double-sided mesh (front and
// back in distinct colours, an optional checker), wireframe, springs coloured by strain,
// colliders (spheres, capsules, boxes, meshes; planes as a ground grid), pinned and highlighted
// particles. The same code draws into the viewer's window and into `drape render`'s offscreen
// framebuffer.
//
// Needs a current OpenGL 3.3 core context whose functions libepoxy can load.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <epoxy/gl.h>

#include "drape/cloth.h"
#include "drape/collider.h"
#include "render/camera.h"

namespace drape::render {

/// What to draw besides the cloth.
struct DrawOptions {
  bool wireframe = false;  ///< triangle edges over the shaded cloth
  bool springs = false;    ///< spring overlay coloured by strain (blue 0 → red strain_scale)
  uint8_t spring_kinds = 1u << static_cast<int>(SpringKind::structural);  ///< bit per SpringKind
  double strain_scale = 0.1;  ///< strain drawn fully red (0.1 = 10% stretched or compressed)
  bool checker = true;        ///< checker texture on the cloth, so folds and stretch read
  bool pins = true;           ///< mark pinned particles
  int32_t highlighted = -1;   ///< particle drawn as a large marker (under the cursor), −1: none
  int32_t held = -1;          ///< particle being dragged, −1: none
};

/// Pixel rectangle in the framebuffer, OpenGL convention (origin bottom-left).
struct PixelRect {
  int x = 0;
  int y = 0;
  int width = 1;
  int height = 1;
};

class Renderer {
 public:
  /// Compiles the shaders and builds the static meshes. Throws std::runtime_error with the
  /// driver's log when a shader fails to compile.
  Renderer();
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  /// Uploads the cloth. A state with a non-finite position is refused (returns false) and the
  /// last good one stays on screen, so a diverged simulation never draws garbage.
  bool update(const ClothModel& model, const ClothState& state);

  /// Clears `rect` and draws the last uploaded cloth (whose model is `model`: its springs feed
  /// the overlay) and the colliders into it.
  void draw(const OrbitCamera& camera, const PixelRect& rect, const ClothModel& model,
            const std::vector<Collider>& colliders, const DrawOptions& options);

 private:
  struct Mesh {
    GLuint vao = 0, position = 0, normal = 0, uv = 0, index = 0;
    GLsizei count = 0;
  };
  void draw_lines(const std::vector<float>& data, GLenum mode, const glm::mat4& view_proj,
                  float point_size);
  void draw_shape(const Collider& c);
  static void delete_mesh(Mesh& m);

  GLuint surface_ = 0;     // lit surfaces: cloth, spheres, ground
  GLuint lines_ = 0;       // coloured lines and round points
  GLuint background_ = 0;  // vertical gradient
  GLuint empty_vao_ = 0;
  Mesh cloth_, sphere_, ground_;
  Mesh shape_;  // the capsule or box drawn last
  // Mesh colliders' triangles by shape (held, so an address is never reused for another).
  std::vector<std::pair<std::shared_ptr<const TriangleShape>, Mesh>> meshes_;
  GLuint line_vao_ = 0, line_vbo_ = 0;
  std::vector<float> line_data_;
  // The last uploaded cloth, as floats for the GPU and as positions for the overlays.
  std::vector<float> positions_, normals_;
  std::vector<Vec3> x_;
  std::vector<uint8_t> pinned_;
  uint64_t uploaded_model_ = 0;  // the model (ClothModel::id) whose triangles are in the buffers
};

/// Reads `rect` of the current read framebuffer as RGBA rows, top row first.
std::vector<uint8_t> read_pixels(const PixelRect& rect);

/// Writes RGBA rows (top row first) as a PNG, as io::OutputFile does. Throws io::OutputError
/// when it cannot.
void write_png(const std::string& file, int width, int height, const std::vector<uint8_t>& rgba);

}  // namespace drape::render
