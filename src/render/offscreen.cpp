#include "render/offscreen.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include <epoxy/egl.h>
#include <epoxy/gl.h>

namespace drape::render {

namespace {

std::string egl_error(const char* what) {
  char code[32];
  std::snprintf(code, sizeof code, " (EGL error 0x%04x)", eglGetError());
  return std::string(what) + code;
}

}  // namespace

OffscreenContext::OffscreenContext(int width, int height, int samples)
    : width_(width), height_(height) {
  if (width <= 0 || height <= 0) throw std::runtime_error("the image size must be positive");
  if (!epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_MESA_platform_surfaceless"))
    throw std::runtime_error(
        "EGL offers no surfaceless platform (EGL_MESA_platform_surfaceless): install Mesa's EGL "
        "(libegl-mesa0, libgl1-mesa-dri)");
  EGLDisplay display =
      eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  if (display == EGL_NO_DISPLAY) throw std::runtime_error(egl_error("no surfaceless EGL display"));
  EGLint major = 0, minor = 0;
  if (!eglInitialize(display, &major, &minor))
    throw std::runtime_error(egl_error("cannot initialise EGL"));
  display_ = display;
  if (!eglBindAPI(EGL_OPENGL_API)) {
    eglTerminate(display);
    throw std::runtime_error(egl_error("EGL offers no desktop OpenGL"));
  }
  // No surface: the context draws only into framebuffer objects.
  const EGLint config_attribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, 0,
                                   EGL_NONE};
  EGLConfig config = nullptr;
  EGLint configs = 0;
  const bool no_config = epoxy_has_egl_extension(display, "EGL_KHR_no_config_context");
  if (!eglChooseConfig(display, config_attribs, &config, 1, &configs) || configs < 1) {
    if (!no_config) {
      eglTerminate(display);
      throw std::runtime_error(egl_error("no EGL configuration for desktop OpenGL"));
    }
    config = EGL_NO_CONFIG_KHR;
  }
  const EGLint context_attribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                                    3,
                                    EGL_CONTEXT_MINOR_VERSION,
                                    3,
                                    EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                    EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                    EGL_NONE};
  EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, context_attribs);
  if (context == EGL_NO_CONTEXT) {
    eglTerminate(display);
    throw std::runtime_error(egl_error("cannot create an OpenGL 3.3 core context with EGL"));
  }
  context_ = context;
  if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
    eglDestroyContext(display, context);
    eglTerminate(display);
    throw std::runtime_error(egl_error("cannot make the EGL context current"));
  }

  GLint max_samples = 0;
  glGetIntegerv(GL_MAX_SAMPLES, &max_samples);
  samples_ = std::clamp(samples, 0, static_cast<int>(max_samples));
  glGenFramebuffers(1, &fbo_);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glGenRenderbuffers(1, &colour_);
  glBindRenderbuffer(GL_RENDERBUFFER, colour_);
  glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples_, GL_RGBA8, width, height);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colour_);
  glGenRenderbuffers(1, &depth_);
  glBindRenderbuffer(GL_RENDERBUFFER, depth_);
  glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples_, GL_DEPTH_COMPONENT24, width, height);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw std::runtime_error("the offscreen framebuffer is incomplete");

  glGenFramebuffers(1, &resolve_fbo_);
  glBindFramebuffer(GL_FRAMEBUFFER, resolve_fbo_);
  glGenRenderbuffers(1, &resolve_colour_);
  glBindRenderbuffer(GL_RENDERBUFFER, resolve_colour_);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, resolve_colour_);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw std::runtime_error("the offscreen resolve framebuffer is incomplete");
  bind();
}

OffscreenContext::~OffscreenContext() {
  if (!display_) return;
  if (context_) {
    const GLuint buffers[] = {colour_, depth_, resolve_colour_};
    glDeleteRenderbuffers(3, buffers);
    const GLuint fbos[] = {fbo_, resolve_fbo_};
    glDeleteFramebuffers(2, fbos);
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(display_, context_);
  }
  eglTerminate(display_);
}

void OffscreenContext::bind() {
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
}

std::vector<uint8_t> OffscreenContext::read() {
  glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo_);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, resolve_fbo_);
  glBlitFramebuffer(0, 0, width_, height_, 0, 0, width_, height_, GL_COLOR_BUFFER_BIT, GL_NEAREST);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, resolve_fbo_);
  std::vector<uint8_t> pixels = read_pixels(rect());
  bind();
  return pixels;
}

const char* OffscreenContext::renderer_name() const {
  return reinterpret_cast<const char*>(glGetString(GL_RENDERER));
}

}  // namespace drape::render
