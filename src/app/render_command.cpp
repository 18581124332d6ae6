// `drape render SCENE`: simulate and draw frames to PNG without a display (EGL surfaceless,
// Mesa's llvmpipe when there is no GPU), with the viewer's own renderer; optionally pipe them to
// ffmpeg for a video.
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "app/commands.h"
#include "app/runner.h"
#include "app/terminal.h"
#include "drape/error.h"
#include "io/scene_io.h"
#include "render/offscreen.h"
#include "render/renderer.h"

namespace drape::app {

namespace fs = std::filesystem;

namespace {

struct RenderOptions {
  std::string scene;
  std::optional<int64_t> frames;
  int every = 1;
  std::string out;
  std::string size = "960x540";
  std::vector<std::string> sets;
  std::string video;
  double yaw = NAN, pitch = NAN;  // degrees; NaN: the viewer's start view
  double zoom = 0.0;              // scroll notches
  bool wireframe = false;
  bool springs = false;
  bool quiet = false;
  bool force = false;
};

bool on_path(const std::string& program) {
  const char* path = std::getenv("PATH");
  if (!path) return false;
  std::string dirs = path;
  size_t start = 0;
  while (start <= dirs.size()) {
    const size_t end = std::min(dirs.find(':', start), dirs.size());
    const fs::path candidate = fs::path(dirs.substr(start, end - start)) / program;
    if (access(candidate.c_str(), X_OK) == 0) return true;
    start = end + 1;
  }
  return false;
}

// A folder holding frames of an earlier render is refused, so renders never mix.
void prepare_out_dir(const std::string& dir, bool force) {
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
    throw InputError("--out " + dir, "exists and is not a folder");
  if (fs::exists(dir, ec) && !force) {
    for (const auto& entry : fs::directory_iterator(dir, ec))
      if (entry.path().filename().string().rfind("frame_", 0) == 0)
        throw InputError("--out " + dir,
                         "already holds frames of an earlier render; choose another folder or "
                         "pass --force to overwrite");
  }
  fs::create_directories(dir, ec);
  if (ec) throw InputError("--out " + dir, "cannot create the folder: " + ec.message());
}

std::string frame_file(const std::string& dir, int64_t frame) {
  char name[64];
  std::snprintf(name, sizeof name, "frame_%05lld.png", static_cast<long long>(frame));
  return (fs::path(dir) / name).string();
}

// One shell word, whatever the text holds.
std::string shell_quote(const std::string& text) {
  std::string quoted = "'";
  for (char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

// Frames go to ffmpeg as raw RGBA on its standard input.
class VideoPipe {
 public:
  VideoPipe(const std::string& file, int width, int height, double fps) {
    char format[256];
    std::snprintf(format, sizeof format, "-f rawvideo -pix_fmt rgba -s %dx%d -r %.6g -i - ", width,
                  height, fps);
    // yuv420p (what players expect) needs even sizes: pad by a pixel where needed.
    const std::string command = "ffmpeg -y -loglevel error " + std::string(format) +
                                "-vf 'pad=ceil(iw/2)*2:ceil(ih/2)*2' -c:v libx264 "
                                "-pix_fmt yuv420p " +
                                shell_quote(file);
    // An ffmpeg that quits early must fail a write, not kill drape with SIGPIPE.
    std::signal(SIGPIPE, SIG_IGN);
    pipe_ = popen(command.c_str(), "w");
    if (!pipe_) throw std::runtime_error("cannot start ffmpeg");
  }
  ~VideoPipe() { close(); }
  void write(const std::vector<uint8_t>& rgba) {
    if (pipe_ && std::fwrite(rgba.data(), 1, rgba.size(), pipe_) != rgba.size())
      throw std::runtime_error("ffmpeg stopped taking frames");
  }
  int close() {
    if (!pipe_) return 0;
    const int status = pclose(pipe_);
    pipe_ = nullptr;
    return status;
  }

 private:
  FILE* pipe_ = nullptr;
};

int render(const RenderOptions& o) {
  using clock = std::chrono::steady_clock;
  std::optional<Simulation> sim;
  int width = 0, height = 0;
  int64_t frames = 0;
  std::string out = o.out;
  try {
    parse_size("--size", o.size, width, height);
    const SceneDef def = io::load_scene(o.scene, o.sets);
    frames = o.frames ? *o.frames : frame_count(def);
    try {
      if (!o.force) check_memory(def);
      sim.emplace(def);
      if (!o.force) check_work(*sim, frames);
    } catch (const InputError& e) {
      throw InputError(o.scene + ": " + e.path(), e.problem());
    }
    if (!o.video.empty() && !on_path("ffmpeg"))
      throw InputError("--video",
                       "ffmpeg is not installed (apt-get install ffmpeg); without "
                       "--video, drape render writes the frames as PNG files");
    if (out.empty() && o.video.empty()) out = (fs::path("out") / def.name).string();
    if (!out.empty()) prepare_out_dir(out, o.force);
  } catch (const InputError& e) {
    std::fprintf(stderr, "drape: error: %s\n", e.what());
    return kExitBadInput;
  }

  std::unique_ptr<render::OffscreenContext> context;
  std::unique_ptr<render::Renderer> renderer;
  try {
    context = std::make_unique<render::OffscreenContext>(width, height);
    renderer = std::make_unique<render::Renderer>();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "drape: error: no offscreen OpenGL 3.3 context: %s\n", e.what());
    return kExitNoGraphics;
  }

  render::OrbitCamera camera =
      render::default_camera(sim->state().x, sim->colliders(), double(width) / height);
  if (std::isfinite(o.yaw)) camera.yaw = o.yaw * M_PI / 180.0;
  if (std::isfinite(o.pitch)) camera.pitch = o.pitch * M_PI / 180.0;
  camera.zoom(o.zoom);
  render::DrawOptions draw;
  draw.wireframe = o.wireframe;
  draw.springs = o.springs;

  std::unique_ptr<VideoPipe> video;
  if (!o.video.empty())
    video =
        std::make_unique<VideoPipe>(o.video, width, height, 1.0 / (sim->def().solver.dt * o.every));

  int64_t written = 0;
  double render_ms = 0.0;
  std::string last_file;
  auto draw_frame = [&](const Simulation& s) {
    const auto t0 = clock::now();
    renderer->update(s.model(), s.state());
    context->bind();
    renderer->draw(camera, context->rect(), s.model(), s.colliders(), draw);
    const std::vector<uint8_t> pixels = context->read();
    render_ms += std::chrono::duration<double, std::milli>(clock::now() - t0).count();
    if (!out.empty()) {
      last_file = frame_file(out, s.frame());
      render::write_png(last_file, width, height, pixels);
    }
    if (video) video->write(pixels);
    ++written;
  };
  RunHooks hooks;
  if (!o.quiet) hooks.progress_label = sim->def().name;
  hooks.after_frame = [&](const Simulation& s) {
    if (s.frame() % o.every == 0 || s.frame() == frames) draw_frame(s);
  };
  install_interrupt_handlers();
  RunResult result;
  try {
    result = run_frames(*sim, frames, hooks);
    // A stopped render still draws where it stopped, so the last picture is the last state.
    if (result.status == RunStatus::interrupted && sim->frame() % o.every != 0) draw_frame(*sim);
  } catch (const std::exception& e) {  // a PNG that cannot be written, ffmpeg gone
    std::fprintf(stderr, "drape: error: %s\n", e.what());
    return 1;
  }
  if (video && video->close() != 0) {
    std::fprintf(stderr, "drape: error: ffmpeg failed to write %s\n", o.video.c_str());
    return 1;
  }

  if (!o.quiet) {
    const double sim_ms = result.median_ms();
    std::printf(
        "%s: %lld frames simulated (%.3f ms/frame), %lld drawn at %dx%d in %.1f ms each "
        "(%s, %d samples)\n",
        sim->def().name.c_str(), static_cast<long long>(result.frames), sim_ms,
        static_cast<long long>(written), width, height, written ? render_ms / written : 0.0,
        context->renderer_name(), context->samples());
    if (!last_file.empty())
      std::printf("  pictures in %s/, the last: %s\n", out.c_str(), last_file.c_str());
    if (video) std::printf("  video: %s\n", o.video.c_str());
  }
  return exit_code(o.scene, *sim, result, "the frames so far are kept");
}

}  // namespace

std::function<int()> add_render_command(CLI::App& app) {
  auto o = std::make_shared<RenderOptions>();
  CLI::App* cmd =
      app.add_subcommand("render", "Render a scene's frames to PNG without a display (EGL, Mesa)");
  cmd->add_option("scene", o->scene, "Scene file (JSON)")->required();
  cmd->add_option("--frames", o->frames, "Frames to simulate (default: the scene's duration)")
      ->check(CLI::Range(int64_t{0}, int64_t{1} << 40));
  cmd->add_option("--every", o->every, "Draw every Kth frame (and always the first and last)")
      ->check(CLI::Range(1, 1 << 30));
  cmd->add_option("--out", o->out, "Folder for frame_NNNNN.png (default: out/SCENE_NAME)");
  cmd->add_option("--size", o->size, "Image size WIDTHxHEIGHT in pixels")->capture_default_str();
  cmd->add_option("--set", o->sets, "Override a scene key: KEY=VALUE, e.g. cloth.mass=2")
      ->take_all()
      ->allow_extra_args(false);
  cmd->add_option("--video", o->video, "Also encode the frames into this video with ffmpeg");
  cmd->add_option("--yaw", o->yaw, "Camera angle around the vertical axis, degrees");
  cmd->add_option("--pitch", o->pitch, "Camera angle above the horizon, degrees")
      ->check(CLI::Range(-89.0, 89.0));
  cmd->add_option("--zoom", o->zoom, "Zoom in by this many scroll notches (negative: out)");
  cmd->add_flag("--wireframe", o->wireframe, "Draw the triangle edges");
  cmd->add_flag("--springs", o->springs, "Draw the structural springs coloured by strain");
  cmd->add_flag("--quiet", o->quiet, "No progress bar and no summary");
  cmd->add_flag("--force", o->force,
                "Run beyond the memory and work budgets, and write into a folder that holds an "
                "earlier render's frames");
  return [cmd, o] { return cmd->parsed() ? render(*o) : -1; };
}

}  // namespace drape::app
