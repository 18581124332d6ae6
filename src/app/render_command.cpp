// `drape render SCENE`: simulate and draw frames to PNG without a display (EGL surfaceless,
// Mesa's llvmpipe when there is no GPU), with the viewer's own renderer; optionally pipe them to
// ffmpeg for a video.
#include <unistd.h>

#include <algorithm>
#include <cctype>
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
#include "app/frame_folder.h"
#include "app/options.h"
#include "app/runner.h"
#include "app/terminal.h"
#include "drape/error.h"
#include "io/output_file.h"
#include "io/scene_io.h"
#include "io/shown_text.h"
#include "render/offscreen.h"
#include "render/renderer.h"

namespace drape::app {

namespace fs = std::filesystem;

namespace {

const std::vector<std::string> kPictureExtensions{"png"};

struct RenderOptions {
  std::string scene;
  std::optional<int64_t> frames;
  std::optional<int> every;  // not given: from picture_rate()
  std::string out;
  std::string size = "960x540";
  std::vector<std::string> sets;
  std::string video;
  int threads = 0;
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

// One shell word, whatever the text holds.
std::string shell_quote(const std::string& text) {
  std::string quoted = "'";
  for (char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

bool is_gif(const std::string& file) {
  std::string extension = fs::path(file).extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return extension == ".gif";
}

// Pictures per simulated second when --every is not given: enough to follow the motion, not
// every frame (a 10 s scene at 60 frames a second would be 600 files). A video plays at its
// own rate, so it gets more; a GIF, whose size grows with every frame, fewer.
double picture_rate(const std::string& video) {
  if (video.empty()) return 10.0;
  return is_gif(video) ? 15.0 : 30.0;
}

// Frames go to ffmpeg as raw RGBA on its standard input.
class VideoPipe {
 public:
  VideoPipe(const std::string& file, int width, int height, double fps) : file_(file) {
    char format[256];
    std::snprintf(format, sizeof format, "-f rawvideo -pix_fmt rgba -s %dx%d -r %.6g -i - ", width,
                  height, fps);
    // A GIF takes a palette made from the frames themselves; yuv420p (what video players
    // expect) needs even sizes: pad by a pixel where needed.
    const std::string encode = is_gif(file)
                                   ? "-vf 'split[a][b];[a]palettegen[p];[b][p]paletteuse' "
                                     "-loop 0 "
                                   : "-vf 'pad=ceil(iw/2)*2:ceil(ih/2)*2' -c:v libx264 "
                                     "-pix_fmt yuv420p ";
    const std::string command =
        "ffmpeg -y -loglevel error " + std::string(format) + encode + shell_quote(file);
    // An ffmpeg that quits early must fail a write, not kill drape with SIGPIPE.
    std::signal(SIGPIPE, SIG_IGN);
    // In a session of its own, so the Ctrl-C that stops drape at the end of a frame does not
    // kill ffmpeg mid-file: drape closes the pipe, and ffmpeg finishes the video.
    pipe_ = popen(("exec setsid -w " + command).c_str(), "w");
    if (!pipe_) throw io::OutputError(file + ": cannot start ffmpeg");
  }
  ~VideoPipe() { close(); }
  void write(const std::vector<uint8_t>& rgba) {
    if (pipe_ && std::fwrite(rgba.data(), 1, rgba.size(), pipe_) != rgba.size())
      throw io::OutputError(file_ + ": ffmpeg stopped taking frames");
  }
  int close() {
    if (!pipe_) return 0;
    const int status = pclose(pipe_);
    pipe_ = nullptr;
    return status;
  }

 private:
  std::string file_;
  FILE* pipe_ = nullptr;
};

int render(const RenderOptions& o) {
  using clock = std::chrono::steady_clock;
  use_threads(o.threads);
  std::optional<Simulation> sim;
  int width = 0, height = 0;
  int64_t frames = 0, replaced = 0;
  int every = 1;
  std::string out = o.out;
  const std::string source = io::source_name(o.scene);
  try {
    parse_size("--size", o.size, width, height);
    const SceneDef def = io::load_scene(o.scene, o.sets);
    frames = o.frames ? *o.frames : frame_count(def);
    every = o.every ? *o.every
                    : static_cast<int>(std::max(
                          1.0, std::round(1.0 / (def.solver.dt * picture_rate(o.video)))));    if (!o.video.empty()) {
      if (!on_path("ffmpeg"))
        throw InputError("--video",
                         "ffmpeg is not installed (apt-get install ffmpeg); without "
                         "--video, drape render writes the frames as PNG files");
      if (o.video == "-" || fs::path(o.video).extension().string().size() < 2)
        throw InputError("--video " + o.video,
                         "needs a file name with an extension (.mp4, .mkv, ...): ffmpeg takes "
                         "the container from it");
      io::check_output("--video", o.video);
      check_not_the_scene("--video", o.video, o.scene);
    }
    // The scene's name makes one folder inside out/, whatever characters it holds.
    if (out.empty() && o.video.empty())
      out = (fs::path("out") / io::file_name_from(def.name)).string();
    if (!out.empty()) check_frame_folder("--out", out, kPictureExtensions, o.force);
    if (!o.force)
      check_memory(def, render::estimated_picture_bytes(width, height), "--size " + o.size);
    try {
      sim.emplace(def);
      if (!o.force) check_work(*sim, frames);
    } catch (const InputError& e) {
      throw InputError(source + ": " + e.path(), e.problem());
    }
    if (!out.empty()) replaced = prepare_frame_folder("--out", out, kPictureExtensions);
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
  if (!o.video.empty()) {
    try {
      video = std::make_unique<VideoPipe>(o.video, width, height,
                                          1.0 / (sim->def().solver.dt * every));
    } catch (const io::OutputError& e) {
      std::fprintf(stderr, "drape: error: %s\n", e.what());
      return kExitOutputFailed;
    }
  }
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
      const std::string file = frame_file(out, s.frame(), "png");
      render::write_png(file, width, height, pixels);
      last_file = file;
    }
    if (video) video->write(pixels);
    ++written;
  };
  if (!o.quiet && !o.every) {
    const int64_t pictures = frames / every + 1 + (frames % every != 0 ? 1 : 0);
    std::printf("drawing 1 frame in %d: %lld pictures of %lld frames (--every 1 draws all)\n",
                every, static_cast<long long>(pictures), static_cast<long long>(frames));
    std::fflush(stdout);
  }
  RunHooks hooks;
  hooks.threads = o.threads;
  if (!o.quiet) hooks.progress_label = io::shown(sim->def().name, 30);
  hooks.after_frame = [&](const Simulation& s) {
    if (s.frame() % every == 0 || s.frame() == frames) draw_frame(s);
  };
  install_interrupt_handlers();
  RunResult result = run_frames(*sim, frames, hooks);
  std::vector<std::string> output_errors;
  // A stopped render still draws where it stopped, so the last picture is the last state.
  if (result.status == RunStatus::interrupted && sim->frame() % every != 0) {
    try {
      draw_frame(*sim);
    } catch (const io::OutputError& e) {
      output_errors.push_back(e.what());
    }
  }
  if (video && video->close() != 0)
    output_errors.push_back(o.video + ": ffmpeg failed to write the video");

  if (!o.quiet) {
    const double sim_ms = result.median_ms();
    std::printf(
        "%s: %lld frames simulated (%.3f ms/frame), %lld drawn at %dx%d in %.1f ms each "
        "(%s, %d samples)\n",
        io::shown(sim->def().name).c_str(), static_cast<long long>(result.frames), sim_ms,
        static_cast<long long>(written), width, height, written ? render_ms / written : 0.0,
        context->renderer_name(), context->samples());
    if (!last_file.empty())
      std::printf("  pictures in %s/, the last: %s\n", out.c_str(), last_file.c_str());
    if (replaced > 0)
      std::printf("  an earlier render's %lld pictures were removed first\n",
                  static_cast<long long>(replaced));
    if (video && output_errors.empty()) std::printf("  video: %s\n", o.video.c_str());
    std::fflush(stdout);
  }
  const int code = exit_code(source, *sim, result, "the frames so far are kept");
  for (const std::string& e : output_errors) std::fprintf(stderr, "drape: error: %s\n", e.c_str());
  return output_errors.empty() ? code : kExitOutputFailed;
}

}  // namespace

std::function<int()> add_render_command(CLI::App& app) {
  auto o = std::make_shared<RenderOptions>();
  CLI::App* cmd =
      app.add_subcommand("render", "Render a scene's frames to PNG without a display (EGL, Mesa)");
  cmd->add_option("scene", o->scene, "Scene file (JSON), or - to read it from standard input")
      ->required();
  cmd->add_option("--frames", o->frames, "Frames to simulate (default: the scene's duration)")
      ->check(CLI::Range(int64_t{0}, int64_t{1} << 40));
  cmd->add_option("--every", o->every,
                  "Draw every Kth frame (and always the first and last); default: 10 pictures "
                  "per simulated second (for --video 30, for a GIF 15)")
      ->check(CLI::Range(1, 1 << 30));
  cmd->add_option("--out", o->out,
                  "Folder for frame_NNNNN.png (default: out/NAME, NAME the scene's name with "
                  "characters other than letters, digits and ._-+ made _)")
      ->check(kNonEmpty);
  cmd->add_option("--size", o->size, "Image size WIDTHxHEIGHT in pixels")->capture_default_str();
  cmd->add_option("--set", o->sets, "Override a scene key: KEY=VALUE, e.g. cloth.mass=2")
      ->take_all()
      ->allow_extra_args(false);
  cmd->add_option("--video", o->video,
                  "Also encode the frames into this video with ffmpeg (FILE.mp4, .mkv, .gif, ...)")
      ->check(kNonEmpty);
  cmd->add_option("--yaw", o->yaw, "Camera angle around the vertical axis, degrees")
      ->check(finite_range(-360.0, 360.0));
  cmd->add_option("--pitch", o->pitch, "Camera angle above the horizon, degrees")
      ->check(finite_range(-89.0, 89.0));
  cmd->add_option("--zoom", o->zoom, "Zoom in by this many scroll notches (negative: out)")
      ->check(finite_range(-100.0, 100.0))
      ->capture_default_str();
  add_threads_option(cmd, o->threads);
  cmd->add_flag("--wireframe", o->wireframe, "Draw the triangle edges");
  cmd->add_flag("--springs", o->springs, "Draw the structural springs coloured by strain");
  cmd->add_flag("--quiet", o->quiet, "No progress bar and no summary");
  cmd->add_flag("--force", o->force,
                "Run beyond the memory and work budgets, and write into a folder that holds an "
                "earlier render's frames (which are removed first)");
  cmd->footer(exit_codes_help(
      {kExitOk, kExitBadInput, kExitDiverged, kExitNoGraphics, kExitOutputFailed, 129, 130, 143}));
  return [cmd, o] { return cmd->parsed() ? render(*o) : -1; };
}

}  // namespace drape::app
