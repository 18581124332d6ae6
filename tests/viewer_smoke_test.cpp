// `drape view` under a display (xvfb-run when none is set) and `drape render` through EGL, run
// as a user runs them: every shipped scene is drawn, and the pictures are checked for content
// and for the cloth's colours; a scripted drag must move the picked particle onto the ray.
// Skips, saying why, only where no display or no EGL context can be had (exit code 4).
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "drape_process.h"
#include "shipped_scenes.h"
#include "stb_image.h"
#include "temp_dir.h"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr int kNoGraphics = 4;  // drape's exit code when no display or context can be had

using Result = drape::testing_support::CommandResult;

Result shell(const std::string& command) {
  return drape::testing_support::run_shell(command);
}

bool on_path(const std::string& program) {
  return shell("command -v " + program + " >/dev/null").code == 0;
}

// How to reach a display: the one set, else a virtual one; empty when there is none.
std::string display_prefix() {
  const char* d = std::getenv("DISPLAY");
  if (d && *d) return " ";
  if (on_path("xvfb-run")) return "xvfb-run -a -s '-screen 0 1280x1024x24' ";
  return "";
}

std::string scene(const std::string& name) {
  return std::string(DRAPE_SOURCE_DIR) + "/scenes/" + name + ".json";
}

// What a picture holds, by colour class.
struct Picture {
  int width = 0, height = 0;
  double front = 0.0;        ///< share of pixels in the cloth's front colour (orange)
  double back = 0.0;         ///< share in its back colour (teal)
  double luma_stddev = 0.0;  ///< 0–255
  double cloth() const { return front + back; }
};

// Hue tests that survive shading: orange has red well above blue and above green; teal has
// green well above red and not below blue (the panel's blues have blue above green).
bool front_colour(double r, double g, double b) {
  return r > 40 && r > 1.6 * b + 10 && r > g;
}
bool back_colour(double r, double g, double b) {
  return g > 40 && g > 1.8 * r + 10 && g >= b;
}

Picture analyse(const std::string& file) {
  Picture p;
  int comp = 0;
  unsigned char* data = stbi_load(file.c_str(), &p.width, &p.height, &comp, 3);
  if (!data) {
    ADD_FAILURE() << file << ": cannot read the PNG";
    return p;
  }
  const size_t n = static_cast<size_t>(p.width) * p.height;
  double sum = 0.0, sum2 = 0.0;
  size_t front = 0, back = 0;
  for (size_t i = 0; i < n; ++i) {
    const double r = data[3 * i], g = data[3 * i + 1], b = data[3 * i + 2];
    front += front_colour(r, g, b);
    back += back_colour(r, g, b);
    const double y = 0.299 * r + 0.587 * g + 0.114 * b;
    sum += y;
    sum2 += y * y;
  }
  stbi_image_free(data);
  p.front = double(front) / n;
  p.back = double(back) / n;
  p.luma_stddev = std::sqrt(std::max(0.0, sum2 / n - (sum / n) * (sum / n)));
  std::printf("%s: front %.3f, back %.3f, luma spread %.1f\n", file.c_str(), p.front, p.back,
              p.luma_stddev);
  return p;
}

// Pixels of either cloth colour in the rectangle [x0, x1) × [y0, y1) of a picture.
int cloth_pixels(const std::string& file, int x0, int y0, int x1, int y1) {
  int width = 0, height = 0, comp = 0;
  unsigned char* data = stbi_load(file.c_str(), &width, &height, &comp, 3);
  if (!data) {
    ADD_FAILURE() << file << ": cannot read the PNG";
    return -1;
  }
  int count = 0;
  for (int y = std::max(0, y0); y < std::min(height, y1); ++y)
    for (int x = std::max(0, x0); x < std::min(width, x1); ++x) {
      const unsigned char* p = data + 3 * (static_cast<size_t>(y) * width + x);
      count += front_colour(p[0], p[1], p[2]) || back_colour(p[0], p[1], p[2]);
    }
  stbi_image_free(data);
  return count;
}

class ViewerSmoke : public drape::testing_support::TempDirTest {
 protected:
  ViewerSmoke() : TempDirTest("drape_view_") {}
  static void SetUpTestSuite() {
    // In the sanitizer build, the drape processes these tests start load the OpenGL drivers
    // (Mesa, llvmpipe, X11), which leak a few bytes at exit from modules they have already
    // unloaded, so the reports name nothing to suppress. Leak checking is off in those child
    // processes only (AddressSanitizer's other checks stay on); the leak checks of our own code
    // run in drape_render_tests. A value the caller set wins.
    setenv("LSAN_OPTIONS", "detect_leaks=0", 0);
  }
  /// A folder holding a stand-in ffmpeg, to put first on the PATH: it records its arguments in
  /// OUTPUT.args and the count of bytes it was sent in OUTPUT, so the pipe is checked whether or
  /// not the real one is installed.
  std::string fake_ffmpeg() const {
    const fs::path bin = dir_ / "bin";
    fs::create_directories(bin);
    {
      std::ofstream fake(bin / "ffmpeg");
      fake << "#!/bin/sh\n"
              "for last in \"$@\"; do :; done\n"
              "printf '%s\\n' \"$@\" > \"$last.args\"\n"
              "wc -c > \"$last\"\n";
    }
    fs::permissions(bin / "ffmpeg", fs::perms::owner_all);
    return bin.string();
  }
  /// Runs `drape view` on a shipped scene for 30 frames in a 640×480 window without the panel
  /// (the 3D view is the whole window) with `args` (a scripted drag), and reads its report into
  /// `out`. Skips the test without a display.
  void view_report(const std::string& name, const std::string& args, json& out) {
    const std::string prefix = display_prefix();
    if (prefix.empty()) GTEST_SKIP() << "no display: DISPLAY is not set and xvfb-run is missing";
    const std::string report = path(name + "-report.json");
    const Result r =
        shell(prefix + DRAPE_EXE + " view " + scene(name) +
              " --frames 30 --size 640x480 --no-panel " + args + " --report " + report);
    if (r.code == kNoGraphics) GTEST_SKIP() << "no OpenGL 3.3 display: " << r.output;
    ASSERT_EQ(r.code, 0) << r.output;
    std::ifstream in(report);
    out = json::parse(in);
  }
};

TEST_F(ViewerSmoke, EveryShippedSceneShowsTheClothInTheViewer) {
  const std::string prefix = display_prefix();
  if (prefix.empty()) GTEST_SKIP() << "no display: DISPLAY is not set and xvfb-run is missing";
  for (const std::string& name : drape::testing_support::shipped_scene_names()) {
    const std::string shot = path(std::string(name) + ".png");
    const Result r = shell(prefix + DRAPE_EXE + " view " + scene(name) +
                           " --frames 45 --size 800x500 --screenshot " + shot);
    if (r.code == kNoGraphics) GTEST_SKIP() << "no OpenGL 3.3 display: " << r.output;
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_NE(r.output.find("screenshot: " + shot), std::string::npos) << r.output;
    const Picture p = analyse(shot);
    EXPECT_EQ(p.width, 800);
    EXPECT_EQ(p.height, 500);
    EXPECT_GT(p.luma_stddev, 15.0) << name << ": the picture is nearly uniform";
    // The cloth fills a fair part of the 3D view (right of the panel, about half the window)
    // and not all of it; a horizontal cloth seen from 17° above covers least (about 5%).
    EXPECT_GT(p.cloth(), 0.025) << name << ": front " << p.front << ", back " << p.back;
    EXPECT_LT(p.cloth(), 0.6) << name << ": front " << p.front << ", back " << p.back;
  }
}

TEST_F(ViewerSmoke, EveryShippedSceneRendersThroughEgl) {
  for (const std::string& name : drape::testing_support::shipped_scene_names()) {
    const std::string out = path(name);
    const Result r = shell(std::string(DRAPE_EXE) + " render " + scene(name) +
                           " --frames 40 --every 20 --size 400x300 --quiet --out " + out);
    if (r.code == kNoGraphics) GTEST_SKIP() << "no EGL context: " << r.output;
    ASSERT_EQ(r.code, 0) << r.output;
    for (const char* frame : {"frame_00000.png", "frame_00020.png", "frame_00040.png"})
      EXPECT_TRUE(fs::exists(fs::path(out) / frame)) << name << " lacks " << frame;
    const Picture p = analyse((fs::path(out) / "frame_00040.png").string());
    EXPECT_EQ(p.width, 400);
    EXPECT_EQ(p.height, 300);
    EXPECT_GT(p.luma_stddev, 15.0) << name << ": the picture is nearly uniform";
    EXPECT_GT(p.cloth(), 0.05) << name << ": front " << p.front << ", back " << p.back;
    EXPECT_LT(p.cloth(), 0.8) << name << ": front " << p.front << ", back " << p.back;
  }
}

TEST_F(ViewerSmoke, BothSidesOfTheClothShowInTheirOwnColours) {
  // The hang scene seen from behind (yaw 180°) shows the back, from the front the front.
  const std::string front = path("front"), back = path("back");
  const std::string base =
      std::string(DRAPE_EXE) + " render " + scene("hang") + " --frames 1 --size 200x150 --quiet";
  Result r = shell(base + " --out " + front);
  if (r.code == kNoGraphics) GTEST_SKIP() << "no EGL context: " << r.output;
  ASSERT_EQ(r.code, 0) << r.output;
  r = shell(base + " --yaw 180 --out " + back);
  ASSERT_EQ(r.code, 0) << r.output;
  const Picture f = analyse((fs::path(front) / "frame_00001.png").string());
  const Picture b = analyse((fs::path(back) / "frame_00001.png").string());
  EXPECT_GT(f.front, 0.1);
  EXPECT_LT(f.back, 0.01);
  EXPECT_GT(b.back, 0.1);
  EXPECT_LT(b.front, 0.01);
}

TEST_F(ViewerSmoke, TheCameraKeepsABlownClothWholeInTheViewBesideThePanel) {
  const std::string prefix = display_prefix();
  if (prefix.empty()) GTEST_SKIP() << "no display: DISPLAY is not set and xvfb-run is missing";
  // The gusts blow the wind scene's cloth toward the eye and across the view, out of the start
  // view that framed it hanging: it must stay whole in the 3D view, right of the 360-unit
  // panel, none of it cut at the view's edges.
  const std::string shot = path("wind.png");
  const Result r = shell(prefix + DRAPE_EXE + " view " + scene("wind") +
                         " --frames 60 --size 1280x720 --screenshot " + shot);
  if (r.code == kNoGraphics) GTEST_SKIP() << "no OpenGL 3.3 display: " << r.output;
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_GT(analyse(shot).cloth(), 0.03);
  constexpr int kPanel = 360, kEdge = 6;
  EXPECT_EQ(cloth_pixels(shot, 0, 0, kPanel + kEdge, 720), 0) << "cut at the panel";
  EXPECT_EQ(cloth_pixels(shot, 1280 - kEdge, 0, 1280, 720), 0) << "cut at the right";
  EXPECT_EQ(cloth_pixels(shot, kPanel, 0, 1280, kEdge), 0) << "cut at the top";
  EXPECT_EQ(cloth_pixels(shot, kPanel, 720 - kEdge, 1280, 720), 0) << "cut at the bottom";
}

TEST_F(ViewerSmoke, ScriptedDragHoldsThePickedParticleOnTheRay) {
  // The default camera centres the hanging cloth, so the press lands on its middle. Drag 100
  // units right, 20 up.
  json j;
  view_report("hang", "--drag 320,240,420,220", j);
  if (IsSkipped() || HasFatalFailure()) return;
  const json& d = j.at("drag");
  const int picked = d.at("picked");
  ASSERT_GE(picked, 0) << "nothing picked at the cloth's centre: " << j.dump(2);
  // The middle of the 32 × 32 grid, give or take the pick radius.
  EXPECT_NEAR(picked % 32, 15.5, 2.5) << j.dump(2);
  EXPECT_NEAR(picked / 32, 15.5, 2.5) << j.dump(2);

  auto vec = [](const json& a) { return std::array<double, 3>{a[0], a[1], a[2]}; };
  const auto x = vec(d.at("position")), o = vec(d.at("ray_origin")),
             dir = vec(d.at("ray_direction")), start = vec(d.at("start"));
  const double along = d.at("along");
  // Held where the ray through the final cursor position says: o + d·dir.
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(x[k], o[k] + along * dir[k], 1e-9) << k;
  // The eye looks at the cloth from about 5 m; 100 units right moves it well to the right, and
  // 20 units up a little up.
  EXPECT_GT(along, 2.0);
  EXPECT_GT(x[0] - start[0], 0.4) << j.dump(2);
  EXPECT_GT(x[1] - start[1], 0.0) << j.dump(2);
}

TEST_F(ViewerSmoke, ShiftDragCarriesTheColliderUnderTheCursor) {
  // The sphere scene's ball (centre at the origin) sits below the middle of the view; Shift-drag
  // it 100 units right.
  json j;
  view_report("sphere", "--drag 320,300,420,300 --carry", j);
  if (IsSkipped() || HasFatalFailure()) return;
  ASSERT_TRUE(j.contains("carry")) << j.dump(2);
  const json& c = j.at("carry");
  ASSERT_EQ(c.at("picked"), 0) << "the ball was not picked: " << j.dump(2);
  EXPECT_FALSE(j.contains("drag")) << "a particle was dragged too";
  // Carried where the hand went: well to the right in the view, and the ball is there.
  EXPECT_GT(double(c.at("offset")[0]), 0.3) << j.dump(2);
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(double(c.at("center")[k]), double(c.at("offset")[k]), 1e-12) << k;
}

TEST_F(ViewerSmoke, VideoFramesArePipedToFfmpeg) {
  const std::string bin = fake_ffmpeg();
  const std::string video = path("it's a clip.mp4");  // a quote and a space survive the shell
  const Result r = shell("cd " + dir_.string() + " && PATH=" + bin + ":$PATH " +
                         DRAPE_EXE + " render " + scene("hang") +
                         " --frames 10 --every 5 --size 64x48 --quiet --video \"" + video + "\"");
  if (r.code == kNoGraphics) GTEST_SKIP() << "no EGL context: " << r.output;
  ASSERT_EQ(r.code, 0) << r.output;
  std::ifstream bytes(video);
  long long count = 0;
  bytes >> count;
  EXPECT_EQ(count, 3LL * 64 * 48 * 4);  // frames 0, 5 and 10 as raw RGBA
  std::ifstream args(video + ".args");
  const std::string text((std::istreambuf_iterator<char>(args)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("64x48"), std::string::npos) << text;
  EXPECT_NE(text.find("rgba"), std::string::npos) << text;
  EXPECT_NE(text.find("pad=ceil(iw/2)*2:ceil(ih/2)*2"), std::string::npos) << text;
  EXPECT_NE(text.find("\n12\n"), std::string::npos) << "12 frames/s: 1 / (dt * every)\n" << text;
  EXPECT_FALSE(fs::exists(path("out"))) << "no PNG folder in the working folder without --out";
}

TEST_F(ViewerSmoke, WithoutEveryARenderDrawsTenPicturesASecondAndAGifFifteen) {
  // 60 frames at 1/60 s: every 6th frame, 0 to 60, is 11 pictures, and the render says so. A
  // small cloth: what is checked is which pictures are made.
  const std::string out = path("pictures");
  const std::string hang = scene("hang") + " --set cloth.resolution=[8,8]";
  Result r = shell(std::string(DRAPE_EXE) + " render " + hang + " --frames 60 --size 64x48 --out " +
                   out);
  if (r.code == kNoGraphics) GTEST_SKIP() << "no EGL context: " << r.output;
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("11 pictures of 60 frames"), std::string::npos) << r.output;
  int pictures = 0;
  for (const auto& entry : fs::directory_iterator(out)) pictures += entry.path().extension() == ".png";
  EXPECT_EQ(pictures, 11);
  EXPECT_TRUE(fs::exists(fs::path(out) / "frame_00006.png"));
  // A GIF: every 4th frame (15 a second), a palette from its own frames, looping.
  const std::string gif = path("clip.GIF");
  r = shell("PATH=" + fake_ffmpeg() + ":$PATH " + DRAPE_EXE + " render " + hang +
            " --frames 60 --size 64x48 --quiet --video " + gif);
  ASSERT_EQ(r.code, 0) << r.output;
  std::ifstream bytes(gif);
  long long count = 0;
  bytes >> count;
  EXPECT_EQ(count, 16LL * 64 * 48 * 4);  // frames 0, 4, ..., 60
  std::ifstream args(gif + ".args");
  const std::string text((std::istreambuf_iterator<char>(args)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("palettegen"), std::string::npos) << text;
  EXPECT_NE(text.find("-loop"), std::string::npos) << text;
  EXPECT_EQ(text.find("libx264"), std::string::npos) << text;
  EXPECT_NE(text.find("\n15\n"), std::string::npos) << text;
}

TEST_F(ViewerSmoke, RenderInterruptedKeepsTheFramesSoFarAndExits130) {
  const std::string out = path("interrupted");
  const Result r = shell("bash -c '" + std::string(DRAPE_EXE) + " render " + scene("hang") +
                         " --frames 100000 --every 5 --size 200x150 --quiet --out " + out +
                         " & pid=$!; sleep 2; kill -INT $pid; wait $pid'");
  if (r.code == kNoGraphics) GTEST_SKIP() << "no EGL context: " << r.output;
  EXPECT_EQ(r.code, 130) << r.output;
  // Whole PNGs only: the first frame, and the frame the run stopped at.
  int pictures = 0;
  for (const auto& entry : fs::directory_iterator(out)) {
    EXPECT_EQ(entry.path().extension(), ".png") << entry.path();
    EXPECT_GT(fs::file_size(entry.path()), 100u) << entry.path();
    ++pictures;
  }
  EXPECT_GE(pictures, 2);
  EXPECT_TRUE(fs::exists(fs::path(out) / "frame_00000.png"));
}

TEST_F(ViewerSmoke, WithoutADisplayTheViewerSaysSoAndExits) {
  const Result r = shell(std::string("env -u DISPLAY -u WAYLAND_DISPLAY ") + DRAPE_EXE + " view " +
                         scene("hang"));
  EXPECT_EQ(r.code, kNoGraphics) << r.output;
  EXPECT_NE(r.output.find("no display"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("drape render"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("xvfb-run"), std::string::npos) << r.output;
}

TEST_F(ViewerSmoke, RenderRejectsBadInputWithExitCode2) {
  const std::string exe = DRAPE_EXE;
  Result r = shell(exe + " render " + scene("hang") + " --size 12x9000 --out " + path("a"));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("--size"), std::string::npos) << r.output;
  r = shell(exe + " render " + path("missing.json") + " --out " + path("b"));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("missing.json"), std::string::npos) << r.output;
  r = shell(exe + " render " + scene("hang") + " --set cloth.mass=-1 --out " + path("c"));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("cloth.mass"), std::string::npos) << r.output;
  // The budgets that protect the machine hold for render and view as for run.
  r = shell(exe + " render " + scene("hang") + " --set cloth.resolution=[3000,3000] --out " +
            path("d"));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("GiB budget"), std::string::npos) << r.output;
  r = shell(exe + " render " + scene("hang") + " --set solver.dt=1e-6 --frames 100000000 --out " +
            path("e"));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("hours of work"), std::string::npos) << r.output;
  r = shell("DISPLAY=:0 " + exe + " view " + scene("hang") + " --set cloth.resolution=[3000,3000]");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("GiB budget"), std::string::npos) << r.output;
  for (const char* folder : {"d", "e"}) EXPECT_FALSE(fs::exists(path(folder))) << folder;
  if (!on_path("ffmpeg")) {
    r = shell(exe + " render " + scene("hang") + " --frames 1 --video " + path("v.mp4"));
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_NE(r.output.find("ffmpeg is not installed"), std::string::npos) << r.output;
  }
}

}  // namespace
