// An OpenGL 3.3 core context with no display: EGL on Mesa's surfaceless platform (llvmpipe
// when there is no GPU), drawing into a multisampled framebuffer object.
#pragma once

#include <cstdint>
#include <vector>

#include "render/renderer.h"

namespace drape::render {

/// An upper estimate of the memory drawing a width × height picture takes, for budgets checked
/// before any drawing: 48 bytes per pixel (measured: 46 with Mesa's llvmpipe at 2048² and
/// 4096², 4 samples: the multisampled colour and depth, the resolved copy, the pixels read
/// back, their RGB copy and the PNG encoder's buffers), the same for a viewer window.
inline int64_t estimated_picture_bytes(int width, int height) {
  return int64_t{48} * width * height;
}

class OffscreenContext {
 public:
  /// Creates the context and a width × height framebuffer with `samples` samples per pixel
  /// (fewer when the driver offers fewer), and makes it current. Throws std::runtime_error
  /// saying what is missing when EGL or the context cannot be had.
  OffscreenContext(int width, int height, int samples = 4);
  ~OffscreenContext();
  OffscreenContext(const OffscreenContext&) = delete;
  OffscreenContext& operator=(const OffscreenContext&) = delete;

  int width() const { return width_; }
  int height() const { return height_; }
  int samples() const { return samples_; }
  /// The whole framebuffer, to draw into.
  PixelRect rect() const { return {0, 0, width_, height_}; }
  /// Binds the framebuffer for drawing.
  void bind();
  /// Resolves the samples and returns RGBA rows, top row first.
  std::vector<uint8_t> read();
  /// The driver's name, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)".
  const char* renderer_name() const;

 private:
  void* display_ = nullptr;
  void* context_ = nullptr;
  int width_ = 0, height_ = 0, samples_ = 0;
  unsigned fbo_ = 0, colour_ = 0, depth_ = 0;      // drawn into (multisampled)
  unsigned resolve_fbo_ = 0, resolve_colour_ = 0;  // read back from
};

}  // namespace drape::render
