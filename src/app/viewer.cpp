#include "app/viewer.h"

#include <epoxy/gl.h>
// GLFW after the loader, and without its own GL header: libepoxy declares the functions.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "app/runner.h"
#include "app/sim_thread.h"
#include "app/terminal.h"
#include "drape/error.h"
#include "drape/material.h"
#include "drape/simulation.h"
#include "io/output_file.h"
#include "io/scene_io.h"
#include "io/shown_text.h"
#include "render/camera.h"
#include "render/picking.h"
#include "render/renderer.h"

namespace drape::app {

namespace fs = std::filesystem;

namespace {

constexpr WindModel kWindModels[] = {WindModel::seed, WindModel::aero};

constexpr float kPanelWidth = 360.0f;    // screen units
constexpr double kPickPixels = 12.0;     // pick radius around the cursor
constexpr double kOrbitPerUnit = 0.008;  // rad per screen unit of right-drag

constexpr const char* kHelpLine =
    "Space play/pause  N step  R reset  F frame  W wireframe  P screenshot  H help  Esc quit";

struct Control {
  const char* input;
  const char* action;
};
constexpr Control kControls[] = {
    {"Left drag", "pull the particle under the cursor"},
    {"Ctrl + left click", "pin or unpin the particle under the cursor"},
    {"Shift + left drag", "carry the collider under the cursor (its velocity is the hand's)"},
    {"Right drag", "orbit the camera"},
    {"Middle drag, Shift + right drag", "pan"},
    {"Scroll", "zoom"},
    {"F", "frame the cloth"},
    {"Space", "pause / play"},
    {"N", "one frame"},
    {"R", "reset the cloth"},
    {"W", "wireframe"},
    {"P", "screenshot (PNG in the working folder)"},
    {"H", "this help"},
    {"Esc", "quit"},
};

bool slider(const char* label, double& v, double lo, double hi, const char* format = "%.3g",
            bool logarithmic = false) {
  return ImGui::SliderScalar(label, ImGuiDataType_Double, &v, &lo, &hi, format,
                             logarithmic ? ImGuiSliderFlags_Logarithmic : 0);
}

bool drag3(const char* label, Vec3& v, float speed) {
  return ImGui::DragScalarN(label, ImGuiDataType_Double, v.data(), 3, speed, nullptr, nullptr,
                            "%.2f");
}

class Viewer {
 public:
  Viewer(const ViewerOptions& o, const SceneDef& def) : o_(o), def_(def), edit_(def) {}
  ~Viewer();
  int run();

 private:
  // Window and context.
  bool open();
  static Viewer& self(GLFWwindow* w) { return *static_cast<Viewer*>(glfwGetWindowUserPointer(w)); }
  render::Viewport viewport() const;  // the 3D view, window units
  render::Ray ray_at(double px, double py) const;
  void frame_camera();
  void start_camera();
  void follow_cloth();
  bool cloth_bounds(Vec3& lo, Vec3& hi) const;

  // Input: the same calls serve the mouse and the scripted drag.
  void press(double px, double py, bool ctrl, bool shift);
  void move(double px, double py);
  void release();
  void on_mouse_button(int button, int action, int mods);
  void on_cursor(double px, double py);
  void on_scroll(double dy);
  void on_key(int key, int action, int mods);

  // Simulation: it runs on its own thread; the window reads snapshots and sends commands.
  bool rebuild(const SceneDef& def);
  void apply_edit(bool new_cloth);
  void open_scene(const std::string& file);

  // Drawing.
  void draw_panel();
  void draw_help();
  void draw_frame();
  bool save_screenshot(const std::string& file);  // says how it went in status_

  ViewerOptions o_;
  SceneDef def_;   // what the simulation was built from
  SceneDef edit_;  // what the panel shows and edits
  std::unique_ptr<SimThread> sim_;
  std::shared_ptr<const SimSnapshot> snap_;   // what is drawn this frame
  std::shared_ptr<const SimSnapshot> drawn_;  // what the renderer holds
  GLFWwindow* window_ = nullptr;
  bool imgui_ = false;
  std::unique_ptr<render::Renderer> renderer_;
  render::OrbitCamera camera_;
  // Until the hand moves the camera or the cloth, the camera follows the cloth: it frames the
  // box the cloth has swept since it was last framed, so a cloth the wind blows toward the eye
  // or across the view stays in the 3D view beside the panel.
  bool follow_ = true;
  Vec3 swept_lo_ = Vec3::Zero(), swept_hi_ = Vec3::Zero();
  render::DrawOptions draw_;
  int32_t held_ = -1;  // the particle the mouse holds (the snapshot may not show it yet)
  double grab_along_ = 0.0;
  // The collider Shift-drag carries (−1: none): the hand's offset and the ray's point when it
  // took hold, so the offset follows the point under the cursor in the view plane.
  int carried_ = -1;
  Vec3 carried_offset_ = Vec3::Zero(), carried_from_ = Vec3::Zero();
  bool paused_ = false;
  bool show_help_ = false;
  bool flick_ = false;  // release with the hand's velocity
  bool orbiting_ = false, panning_ = false;
  double cursor_x_ = 0.0, cursor_y_ = 0.0;
  std::string status_, error_;
  // Where messages for the person go: standard error when the report takes standard output.
  FILE* out_ = o_.report == "-" ? stderr : stdout;
  std::vector<std::string> scene_files_;
  std::string scene_file_;
};

Viewer::~Viewer() {
  sim_.reset();
  renderer_.reset();
  if (imgui_) {
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
  }
  if (window_) glfwDestroyWindow(window_);
  glfwTerminate();
}

bool Viewer::open() {
  if (!glfwInit()) {
    std::fprintf(stderr,
                 "drape view: no display could be opened; draw pictures without one with "
                 "`drape render SCENE`, or run the viewer under `xvfb-run -a drape view`\n");
    return false;
  }
  // After a successful start GLFW's complaints are worth seeing; before, the line above says it.
  glfwSetErrorCallback([](int, const char* text) { std::fprintf(stderr, "glfw: %s\n", text); });
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_RESIZABLE, GLFW_TRUE);
  glfwWindowHint(GLFW_SAMPLES, 4);
  const std::string title = "drape: " + io::shown(def_.name);
  window_ = glfwCreateWindow(o_.width, o_.height, title.c_str(), nullptr, nullptr);
  if (!window_) {  // some servers offer no multisampled visual
    glfwWindowHint(GLFW_SAMPLES, 0);
    window_ = glfwCreateWindow(o_.width, o_.height, title.c_str(), nullptr, nullptr);
  }
  if (!window_) {
    std::fprintf(stderr,
                 "drape view: the display offers no OpenGL 3.3 core context; try "
                 "`drape render SCENE` (EGL, no display needed)\n");
    return false;
  }
  glfwMakeContextCurrent(window_);
  glfwSwapInterval(o_.vsync ? 1 : 0);
  glfwSetWindowUserPointer(window_, this);
  // Ours first: ImGui's backend chains to the callbacks installed before it.
  glfwSetMouseButtonCallback(
      window_, [](GLFWwindow* w, int b, int a, int m) { self(w).on_mouse_button(b, a, m); });
  glfwSetCursorPosCallback(window_,
                           [](GLFWwindow* w, double x, double y) { self(w).on_cursor(x, y); });
  glfwSetScrollCallback(window_, [](GLFWwindow* w, double, double dy) { self(w).on_scroll(dy); });
  glfwSetKeyCallback(window_,
                     [](GLFWwindow* w, int k, int, int a, int m) { self(w).on_key(k, a, m); });

  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini in the user's folder
  ImGui::StyleColorsDark();
  // A slider writes its value across its middle, where its grab can be: a thin, translucent
  // grab leaves the value readable wherever it is (bending c at 0.1 hid it).
  ImGuiStyle& style = ImGui::GetStyle();
  style.GrabMinSize = 4.0f;
  style.Colors[ImGuiCol_SliderGrab].w = 0.55f;
  style.Colors[ImGuiCol_SliderGrabActive].w = 0.75f;
  ImGui_ImplGlfw_InitForOpenGL(window_, true);
  ImGui_ImplOpenGL3_Init("#version 330 core");
  imgui_ = true;
  renderer_ = std::make_unique<render::Renderer>();
  glEnable(GL_MULTISAMPLE);
  return true;
}

render::Viewport Viewer::viewport() const {
  int w = 1, h = 1;
  glfwGetWindowSize(window_, &w, &h);
  const double left = o_.panel ? std::min<double>(kPanelWidth, w - 1) : 0.0;
  return {left, 0.0, std::max(1.0, w - left), std::max(1, h) * 1.0};
}

render::Ray Viewer::ray_at(double px, double py) const {
  const render::Viewport vp = viewport();
  return render::ray_from_pixel(camera_.view(), camera_.projection(vp.aspect()), vp, px, py);
}

// Room for the cloth to sag and swing around the box it fills: a twentieth of its size.
constexpr double kFrameMargin = 0.05;
// The camera backs off when the swept box leaves the middle 96% of the view, and then fits it
// in the middle 90%, so it moves now and then, not every frame.
constexpr double kFollowFraction = 0.96, kFitFraction = 0.9;

bool Viewer::cloth_bounds(Vec3& lo, Vec3& hi) const {
  if (!render::scene_bounds(snap_->state.x, snap_->colliders, lo, hi)) return false;
  const Vec3 margin = Vec3::Constant(kFrameMargin * (hi - lo).maxCoeff());
  lo -= margin;
  hi += margin;
  return true;
}

void Viewer::frame_camera() {
  follow_ = cloth_bounds(swept_lo_, swept_hi_);
  if (follow_) camera_.fit(swept_lo_, swept_hi_, viewport().aspect(), kFitFraction);
}

void Viewer::start_camera() {
  camera_ = render::default_camera(snap_->state.x, snap_->colliders, viewport().aspect());
  frame_camera();
}

void Viewer::follow_cloth() {
  Vec3 lo, hi;
  if (!follow_ || !cloth_bounds(lo, hi)) return;
  swept_lo_ = swept_lo_.cwiseMin(lo);
  swept_hi_ = swept_hi_.cwiseMax(hi);
  const double aspect = viewport().aspect();
  if (!camera_.shows(swept_lo_, swept_hi_, aspect, kFollowFraction))
    camera_.fit(swept_lo_, swept_hi_, aspect, kFitFraction);
}

void Viewer::press(double px, double py, bool ctrl, bool shift) {
  const render::Viewport vp = viewport();
  if (px < vp.x || px >= vp.x + vp.width || py < vp.y || py >= vp.y + vp.height) return;
  const render::Ray ray = ray_at(px, py);
  if (shift) {
    const render::Pick hit = render::first_collider_hit(ray, snap_->colliders);
    if (!hit) return;
    carried_ = hit.index;
    grab_along_ = hit.along;
    carried_from_ = render::drag_target(ray, grab_along_);
    carried_offset_ = snap_->collider_offsets.at(carried_);
    follow_ = false;
    status_ = "carrying collider " + std::to_string(carried_);
    return;
  }
  const render::Pick pick = render::nearest_to_ray(
      ray, snap_->state.x, render::pick_slope(kPickPixels, vp.height, camera_.fov_y));
  if (!pick) return;
  if (ctrl) {
    const bool pinned = snap_->state.pinned[pick.index] != 0;
    sim_->toggle_pin(pick.index);
    status_ = (pinned ? "unpinned particle " : "pinned particle ") + std::to_string(pick.index);
    return;
  }
  held_ = pick.index;
  grab_along_ = pick.along;
  follow_ = false;  // the hand has the cloth: the view must stay where the hand aims
  sim_->grab(pick.index, render::drag_target(ray, grab_along_));
}

void Viewer::move(double px, double py) {
  if (carried_ >= 0) {
    const Vec3 to = render::drag_target(ray_at(px, py), grab_along_);
    sim_->move_collider(carried_, carried_offset_ + (to - carried_from_));
    return;
  }
  if (held_ < 0) return;
  sim_->move_grab(render::drag_target(ray_at(px, py), grab_along_));
}

void Viewer::release() {
  carried_ = -1;
  if (held_ < 0) return;
  sim_->release(flick_);
  held_ = -1;
}

void Viewer::on_mouse_button(int button, int action, int mods) {
  const bool ui = ImGui::GetIO().WantCaptureMouse;
  glfwGetCursorPos(window_, &cursor_x_, &cursor_y_);  // where the press is, moved or not
  if (button == GLFW_MOUSE_BUTTON_LEFT) {
    if (action == GLFW_PRESS && !ui)
      press(cursor_x_, cursor_y_, mods & GLFW_MOD_CONTROL, mods & GLFW_MOD_SHIFT);
    if (action == GLFW_RELEASE) release();
  } else if (button == GLFW_MOUSE_BUTTON_RIGHT) {
    const bool shift = mods & GLFW_MOD_SHIFT;
    orbiting_ = action == GLFW_PRESS && !ui && !shift;
    panning_ = action == GLFW_PRESS && !ui && shift;
  } else if (button == GLFW_MOUSE_BUTTON_MIDDLE) {
    panning_ = action == GLFW_PRESS && !ui;
  }
}

void Viewer::on_cursor(double px, double py) {
  const double dx = px - cursor_x_, dy = py - cursor_y_;
  cursor_x_ = px;
  cursor_y_ = py;
  if (orbiting_) camera_.orbit(-kOrbitPerUnit * dx, kOrbitPerUnit * dy);
  if (panning_) camera_.pan(dx, dy, viewport().height);
  if (orbiting_ || panning_) follow_ = false;
  move(px, py);
}

void Viewer::on_scroll(double dy) {
  if (ImGui::GetIO().WantCaptureMouse) return;
  camera_.zoom(dy);
  follow_ = false;
}

void Viewer::on_key(int key, int action, int /*mods*/) {
  if (action != GLFW_PRESS || ImGui::GetIO().WantCaptureKeyboard) return;
  switch (key) {
    case GLFW_KEY_SPACE:
      paused_ = !paused_;
      break;
    case GLFW_KEY_N:
      paused_ = true;
      sim_->request_step();
      break;
    case GLFW_KEY_R:
      rebuild(edit_);
      break;
    case GLFW_KEY_F:
      frame_camera();
      break;
    case GLFW_KEY_W:
      draw_.wireframe = !draw_.wireframe;
      break;
    case GLFW_KEY_H:
      show_help_ = !show_help_;
      break;
    case GLFW_KEY_P: {
      // The scene's name makes one file name in the working folder, whatever it holds.
      char frame[32];
      std::snprintf(frame, sizeof frame, "_%05lld.png", static_cast<long long>(snap_->frame));
      save_screenshot("drape_" + io::file_name_from(def_.name) + frame);
      break;
    }
    case GLFW_KEY_ESCAPE:
      glfwSetWindowShouldClose(window_, GLFW_TRUE);
      break;
    default:
      break;
  }
}

bool Viewer::rebuild(const SceneDef& def) {
  try {
    // Built here, so a refused definition is reported at once; stepped on the thread.
    auto sim = std::make_unique<Simulation>(def);
    held_ = -1;
    carried_ = -1;
    if (sim_) {
      sim_->replace(std::move(sim));
    } else {
      sim_ = std::make_unique<SimThread>(std::move(sim), o_.frames == 0, o_.threads);
    }
    def_ = def;
    edit_ = def;
    error_.clear();
    if (snap_ && snap_->diverged) paused_ = false;  // the reset the divergence message offers
    return true;
  } catch (const InputError& e) {
    error_ = e.what();
    return false;
  }
}

void Viewer::apply_edit(bool new_cloth) {
  if (new_cloth) {
    rebuild(edit_);
    return;
  }
  try {
    check(edit_);  // out-of-range values are refused here; the thread reports the rest
    sim_->reconfigure(edit_);
    def_ = edit_;
    error_.clear();
  } catch (const InputError& e) {
    error_ = e.what();  // the simulation keeps the last good settings
  }
}

void Viewer::open_scene(const std::string& file) {
  try {
    const SceneDef def = io::load_scene(file);
    if (rebuild(def)) {
      scene_file_ = file;
      sim_->sync();  // frame the new cloth, not the old one
      snap_ = sim_->snapshot();
      start_camera();
      glfwSetWindowTitle(window_, ("drape: " + io::shown(def.name)).c_str());
    }
  } catch (const InputError& e) {
    error_ = e.what();
  }
}

void Viewer::draw_panel() {
  ImGuiIO& io = ImGui::GetIO();
  ImGui::SetNextWindowPos(ImVec2(0, 0));
  ImGui::SetNextWindowSize(ImVec2(kPanelWidth, io.DisplaySize.y));
  ImGui::Begin("drape", nullptr,
               ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);
  ImGui::PushItemWidth(-150.0f);

  // Scene.
  const std::string current =
      scene_file_.empty() ? def_.name : fs::path(scene_file_).stem().string();
  if (ImGui::BeginCombo("scene", current.c_str())) {
    for (const std::string& f : scene_files_) {
      if (ImGui::Selectable(fs::path(f).stem().string().c_str(), f == scene_file_)) open_scene(f);
    }
    ImGui::EndCombo();
  }
  if (ImGui::Button(paused_ ? "Play" : "Pause")) paused_ = !paused_;
  ImGui::SameLine();
  if (ImGui::Button("Step")) {
    paused_ = true;
    sim_->request_step();
  }
  ImGui::SameLine();
  if (ImGui::Button("Reset")) rebuild(edit_);
  ImGui::SameLine();
  if (ImGui::Button("Frame")) frame_camera();

  // Figures.
  const SimSnapshot& s = *snap_;
  const Diagnostics& d = s.diagnostics;
  ImGui::Text("%.0f frames/s   simulation %.2f ms/frame", io.Framerate, s.step_ms);
  ImGui::Text("frame %lld   t = %.2f s   %d substeps/frame", static_cast<long long>(s.frame),
              s.time, s.substeps);
  ImGui::Text("%d particles   %zu springs", s.model->size(), s.model->springs.size());
  ImGui::Text("kinetic energy %.4g J   max strain %.2f%%", d.kinetic_energy, 100.0 * d.max_strain);
  ImGui::Text("self-intersections %lld%s", static_cast<long long>(s.self_intersections),
              s.def.cloth.self_collision.enabled ? "   (self-collision on)" : "");
  if (s.diverged) {
    ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.35f, 0.3f, 1.0f));
    ImGui::TextWrapped("Diverged at frame %lld: %s", static_cast<long long>(s.diverged_frame),
                       s.divergence.c_str());
    ImGui::PopStyleColor();
    if (ImGui::Button("Reset the cloth")) rebuild(edit_);
  }
  for (const std::string* e : {static_cast<const std::string*>(&error_), &s.error}) {
    if (e->empty()) continue;
    ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.6f, 0.2f, 1.0f));
    ImGui::TextWrapped("%s", e->c_str());
    ImGui::PopStyleColor();
  }

  bool live = false, new_cloth = false;
  if (ImGui::CollapsingHeader("Solver", ImGuiTreeNodeFlags_DefaultOpen)) {
    if (ImGui::BeginCombo("method", to_string(edit_.solver.method))) {
      for (Method m : kAllMethods)
        if (ImGui::Selectable(to_string(m), m == edit_.solver.method)) {
          edit_.solver.method = m;
          // Single precision is xpbd's alone; another method goes back to double.
          if (m != Method::xpbd) edit_.solver.precision = Precision::f64;
          live = true;
        }
      ImGui::EndCombo();
    }
    if (edit_.solver.method == Method::xpbd) {
      bool single = edit_.solver.precision == Precision::f32;
      if (ImGui::Checkbox("single precision (faster)", &single)) {
        edit_.solver.precision = single ? Precision::f32 : Precision::f64;
        live = true;
      }
      live |= ImGui::SliderInt("stiff sweeps", &edit_.solver.stiff_sweeps, 0, 40);
      // A material's threads buckle: the line passes' inextensible chains are refused.
      if (!edit_.cloth.material)
        live |= ImGui::SliderInt("line passes", &edit_.solver.line_passes, 0, 12);
      if (edit_.solver.line_passes > 1)
        live |= slider("line relaxation", edit_.solver.line_relaxation, 0.5, 1.9, "%.2f");
    }
    double dt_ms = 1000.0 * edit_.solver.dt;
    if (slider("frame dt (ms)", dt_ms, 1.0, 50.0, "%.2f")) {
      edit_.solver.dt = dt_ms / 1000.0;
      live = true;
    }
    live |= ImGui::SliderInt("substeps (0 auto)", &edit_.solver.substeps, 0, 200);
    live |= slider("safety", edit_.solver.safety, 0.1, 1.0, "%.2f");
  }
  if (ImGui::CollapsingHeader("Cloth", ImGuiTreeNodeFlags_DefaultOpen)) {
    if (edit_.cloth.mesh) {
      // A mesh's shape is its file's: only what the grid and a mesh share is edited here.
      ImGui::TextWrapped("mesh %s", edit_.cloth.mesh_file.c_str());
    } else {
      int res[2] = {edit_.cloth.cols, edit_.cloth.rows};
      if (ImGui::InputInt2("resolution", res)) {
        edit_.cloth.cols = std::clamp(res[0], 2, 512);
        edit_.cloth.rows = std::clamp(res[1], 2, 512);
      }
      new_cloth |= ImGui::IsItemDeactivatedAfterEdit();
      double size[2] = {edit_.cloth.width, edit_.cloth.height};
      const double size_lo = 0.1, size_hi = 10.0;
      if (ImGui::SliderScalarN("size (m)", ImGuiDataType_Double, size, 2, &size_lo, &size_hi,
                               "%.2f")) {
        edit_.cloth.width = size[0];
        edit_.cloth.height = size[1];
      }
      new_cloth |= ImGui::IsItemDeactivatedAfterEdit();
    }
    if (edit_.cloth.material) {
      // A material sets the masses and the stiffness; the seed's mass and springs do not apply.
      // Its numbers are cooked into the cloth: a change makes a new cloth when the slider is let
      // go (a preset at once), and numbers changed by hand are no longer the preset's.
      MaterialDef& m = *edit_.cloth.material;
      if (ImGui::BeginCombo("material", m.name.empty() ? "(own numbers)" : m.name.c_str())) {
        for (const std::string& preset : material_preset_names())
          if (ImGui::Selectable(preset.c_str(), preset == m.name)) {
            m = *material_preset(preset);
            new_cloth = true;
          }
        ImGui::EndCombo();
      }
      auto edited = [&](bool changed) {
        if (changed) m.name.clear();
        new_cloth |= ImGui::IsItemDeactivatedAfterEdit();
      };
      edited(slider("density (kg/m2)", m.density, 0.01, 2.0, "%.3g", true));
      edited(slider("stretch warp (N/m)", m.stretch.x(), 1.0, 1e5, "%.4g", true));
      edited(slider("stretch weft (N/m)", m.stretch.y(), 1.0, 1e5, "%.4g", true));
      edited(slider("shear (N/m)", m.shear, 0.1, 1e4, "%.4g", true));
      Vec2 bending = 1e6 * m.bending;  // shown in µN·m
      const bool bent = slider("bending warp (uN m)", bending.x(), 0.1, 1e4, "%.4g", true);
      edited(bent);
      const bool bent_weft = slider("bending weft (uN m)", bending.y(), 0.1, 1e4, "%.4g", true);
      edited(bent_weft);
      if (bent || bent_weft) m.bending = 1e-6 * bending;
      edited(slider("compression", m.compression, 0.0, 1.0, "%.2f"));
      edited(slider("damping (s)", m.damping, 0.0, 0.1, "%.4f"));
    } else {
      live |= slider("mass (kg)", edit_.cloth.mass, 0.01, 20.0, "%.3g", true);
    }
    live |= ImGui::Checkbox("self-collision", &edit_.cloth.self_collision.enabled);
    if (edit_.cloth.self_collision.enabled)
      live |= slider("layer friction", edit_.cloth.self_collision.friction, 0.0, 2.0, "%.2f");
    SpringParams* kinds[] = {&edit_.cloth.structural, &edit_.cloth.shear, &edit_.cloth.bending};
    const int shown_kinds = edit_.cloth.material ? 0 : kSpringKinds;
    for (int k = 0; k < shown_kinds; ++k) {
      // A mesh has no shear springs: its triangles' edges carry shear.
      if (edit_.cloth.mesh && static_cast<SpringKind>(k) == SpringKind::shear) continue;
      ImGui::PushID(k);
      const std::string name = to_string(static_cast<SpringKind>(k));
      live |= slider((name + " k (N/m)").c_str(), kinds[k]->stiffness, 0.0, 1e5, "%.4g", true);
      live |= slider((name + " c (N s/m)").c_str(), kinds[k]->damping, 0.0, 10.0, "%.3g", true);
      ImGui::PopID();
    }
  }
  if (ImGui::CollapsingHeader("Forces")) {
    live |= drag3("gravity (m/s2)", edit_.forces.gravity, 0.05f);
    const bool material = edit_.cloth.material.has_value();
    double drag = edit_.forces.air_drag_for(material);
    if (slider("air drag (kg/m)", drag, 0.0, 1.0, "%.4f", true)) {
      edit_.forces.air_drag = drag;
      live = true;
    }
    WindDef& w = edit_.forces.wind;
    if (ImGui::BeginCombo("wind model", to_string(w.model))) {
      for (WindModel m : kWindModels)
        if (ImGui::Selectable(to_string(m), m == w.model)) {
          w.model = m;
          live = true;
        }
      ImGui::EndCombo();
    }
    live |= drag3("wind direction", w.direction, 0.02f);
    live |= slider("wind strength", w.strength, 0.0, 30.0, "%.2f");
    live |= slider("wind coefficient", w.coefficient, 0.0, 5.0, "%.2f");
    live |= slider("gust (relative)", w.gust, 0.0, 1.0, "%.2f");
    live |= slider("gust frequency (Hz)", w.gust_frequency, 0.01, 5.0, "%.2f", true);
  }
  if (!edit_.colliders.empty() && ImGui::CollapsingHeader("Colliders")) {
    for (size_t i = 0; i < edit_.colliders.size(); ++i) {
      ColliderDef& c = edit_.colliders[i];
      ImGui::PushID(static_cast<int>(i));
      ImGui::Text("%s %zu", to_string(c.type), i + 1);
      switch (c.type) {
        case ColliderType::sphere:
          live |= drag3("centre (m)", c.center, 0.01f);
          live |= slider("radius (m)", c.radius, 0.05, 3.0, "%.2f");
          break;
        case ColliderType::plane:
          live |= drag3("point (m)", c.center, 0.01f);
          live |= drag3("normal", c.normal, 0.01f);
          break;
        case ColliderType::capsule:
          live |= drag3("end a (m)", c.a, 0.01f);
          live |= drag3("end b (m)", c.b, 0.01f);
          live |= slider("radius (m)", c.radius, 0.05, 3.0, "%.2f");
          break;
        case ColliderType::box:
          live |= drag3("centre (m)", c.center, 0.01f);
          live |= drag3("half extents (m)", c.half_extents, 0.01f);
          live |= drag3("rotate (degrees)", c.rotate, 0.5f);
          break;
        case ColliderType::mesh:
          ImGui::TextWrapped("%s", c.mesh_file.c_str());
          live |= drag3("translate (m)", c.transform.translate, 0.01f);
          break;
      }
      if (c.motion.moves())
        ImGui::Text("moves: %zu keys%s", c.motion.keys.size(), c.motion.loop ? ", looping" : "");
      live |= slider("friction", c.friction, 0.0, 2.0, "%.2f");
      ImGui::PopID();
    }
  }
  if (ImGui::CollapsingHeader("Display", ImGuiTreeNodeFlags_DefaultOpen)) {
    ImGui::Checkbox("wireframe", &draw_.wireframe);
    ImGui::SameLine();
    ImGui::Checkbox("checker", &draw_.checker);
    ImGui::SameLine();
    ImGui::Checkbox("pins", &draw_.pins);
    ImGui::Checkbox("springs by strain", &draw_.springs);
    if (draw_.springs) {
      for (int k = 0; k < kSpringKinds; ++k) {
        ImGui::SameLine();
        bool on = draw_.spring_kinds & (1u << k);
        if (ImGui::Checkbox(to_string(static_cast<SpringKind>(k)), &on))
          draw_.spring_kinds = static_cast<uint8_t>(on ? draw_.spring_kinds | (1u << k)
                                                       : draw_.spring_kinds & ~(1u << k));
      }
      slider("red at strain", draw_.strain_scale, 0.001, 1.0, "%.3f", true);
    }
    ImGui::Checkbox("release with the hand's velocity (flick)", &flick_);
    bool vsync = o_.vsync;
    if (ImGui::Checkbox("vsync", &vsync)) {
      o_.vsync = vsync;
      glfwSwapInterval(vsync ? 1 : 0);
    }
  }
  if (live || new_cloth) apply_edit(new_cloth);

  if (!status_.empty()) {
    ImGui::Separator();
    ImGui::TextWrapped("%s", status_.c_str());
  }
  ImGui::PopItemWidth();
  ImGui::End();
}

void Viewer::draw_help() {
  const ImVec2 size = ImGui::GetIO().DisplaySize;
  ImGui::SetNextWindowPos(ImVec2(0.5f * (size.x + (o_.panel ? kPanelWidth : 0.0f)), 0.5f * size.y),
                          ImGuiCond_Always, ImVec2(0.5f, 0.5f));
  ImGui::Begin("Controls", &show_help_, ImGuiWindowFlags_AlwaysAutoResize);
  if (ImGui::BeginTable("controls", 2, ImGuiTableFlags_RowBg)) {
    for (const Control& c : kControls) {
      ImGui::TableNextColumn();
      ImGui::TextUnformatted(c.input);
      ImGui::TableNextColumn();
      ImGui::TextUnformatted(c.action);
    }
    ImGui::EndTable();
  }
  ImGui::End();
}

void Viewer::draw_frame() {
  int fb_w = 1, fb_h = 1, win_w = 1, win_h = 1;
  glfwGetFramebufferSize(window_, &fb_w, &fb_h);
  glfwGetWindowSize(window_, &win_w, &win_h);
  if (fb_w <= 0 || fb_h <= 0) return;  // minimised

  follow_cloth();

  // Hover: the particle a press would pick.
  draw_.held = held_;
  draw_.highlighted = -1;
  const render::Viewport vp = viewport();
  // A scripted run has no hand on the mouse: wherever the pointer rests, nothing is hovered.
  const bool hand = o_.frames == 0;
  if (hand && draw_.held < 0 && cursor_x_ >= vp.x && !ImGui::GetIO().WantCaptureMouse) {
    draw_.highlighted =
        render::nearest_to_ray(ray_at(cursor_x_, cursor_y_), snap_->state.x,
                               render::pick_slope(kPickPixels, vp.height, camera_.fov_y))
            .index;
  }

  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
  if (o_.panel) draw_panel();
  if (show_help_) draw_help();
  // The keys, along the bottom of the 3D view.
  ImGui::SetNextWindowPos(
      ImVec2(static_cast<float>(vp.x) + 8.0f, ImGui::GetIO().DisplaySize.y - 8.0f),
      ImGuiCond_Always, ImVec2(0.0f, 1.0f));
  ImGui::SetNextWindowBgAlpha(0.45f);
  ImGui::Begin("keys", nullptr,
               ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize |
                   ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoFocusOnAppearing |
                   ImGuiWindowFlags_NoNav | ImGuiWindowFlags_NoInputs);
  ImGui::TextUnformatted(kHelpLine);
  ImGui::End();
  if (snap_->diverged) {
    // Over the 3D view too, so it is seen with the panel hidden or scrolled.
    ImGui::SetNextWindowPos(ImVec2(static_cast<float>(vp.x + 0.5 * vp.width), 10.0f),
                            ImGuiCond_Always, ImVec2(0.5f, 0.0f));
    ImGui::Begin("diverged", nullptr,
                 ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize |
                     ImGuiWindowFlags_NoMove);
    ImGui::TextColored(ImVec4(1.0f, 0.35f, 0.3f, 1.0f),
                       "The simulation diverged at frame %lld and is paused: R resets it",
                       static_cast<long long>(snap_->diverged_frame));
    ImGui::End();
  }
  ImGui::Render();

  if (drawn_ != snap_) {  // upload only what changed
    renderer_->update(*snap_->model, snap_->state);
    drawn_ = snap_;
  }
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glViewport(0, 0, fb_w, fb_h);
  glClearColor(0.1f, 0.1f, 0.1f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  // Window units to framebuffer pixels (they differ on high-density displays).
  const double sx = double(fb_w) / std::max(win_w, 1), sy = double(fb_h) / std::max(win_h, 1);
  const render::PixelRect rect{static_cast<int>(std::lround(vp.x * sx)), 0,
                               std::max(1, static_cast<int>(std::lround(vp.width * sx))),
                               std::max(1, static_cast<int>(std::lround(vp.height * sy)))};
  renderer_->draw(camera_, rect, *snap_->model, snap_->colliders, draw_);
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
}

bool Viewer::save_screenshot(const std::string& file) {
  int fb_w = 1, fb_h = 1;
  glfwGetFramebufferSize(window_, &fb_w, &fb_h);
  glReadBuffer(GL_BACK);
  try {
    render::write_png(file, fb_w, fb_h, render::read_pixels({0, 0, fb_w, fb_h}));
  } catch (const io::OutputError& e) {
    std::fprintf(stderr, "drape: error: %s\n", e.what());
    status_ = e.what();
    return false;
  }
  std::fprintf(out_, "screenshot: %s\n", file.c_str());
  std::fflush(out_);
  status_ = "screenshot: " + file;
  return true;
}

int Viewer::run() {
  if (!rebuild(def_)) {
    std::fprintf(stderr, "drape: error: %s\n", error_.c_str());
    return kExitBadInput;
  }
  snap_ = sim_->snapshot();
  if (!open()) return kExitNoGraphics;
  std::error_code ec;
  // Regular files only: picking a named pipe would wait for a writer with the window frozen.
  for (const auto& entry : fs::directory_iterator(scenes_dir(), ec))
    if (entry.path().extension() == ".json" && entry.is_regular_file(ec))
      scene_files_.push_back(entry.path().string());
  std::sort(scene_files_.begin(), scene_files_.end());
  for (const std::string& f : scene_files_)
    if (fs::equivalent(f, o_.scene, ec)) scene_file_ = f;
  start_camera();

  // Scripted use: one frame per displayed frame, the drag moving before each.
  const bool scripted = o_.frames > 0;
  int32_t dragged = -1;
  int carried = -1;
  nlohmann::json report;
  using clock = std::chrono::steady_clock;
  const auto start = clock::now();
  int64_t shown = 0;
  install_interrupt_handlers();  // Ctrl+C in the terminal closes the window cleanly

  while (!glfwWindowShouldClose(window_)) {
    if (const int signal = interrupt_signal()) return interrupt_exit_code(signal);
    snap_ = sim_->snapshot();  // the input handlers pick from it
    glfwPollEvents();
    if (scripted) {
      if (o_.drag) {
        const auto& g = *o_.drag;
        const int64_t half = std::max<int64_t>(1, o_.frames / 2);
        const double s = std::min(1.0, double(snap_->frame) / double(half));
        if (snap_->frame == 0 && dragged < 0 && carried < 0) {
          press(g[0], g[1], false, o_.carry);
          dragged = held_;
          carried = carried_;
          report[o_.carry ? "carry" : "drag"]["picked"] = o_.carry ? carried : dragged;
          report[o_.carry ? "carry" : "drag"]["along"] = grab_along_;
        }
        move(g[0] + s * (g[2] - g[0]), g[1] + s * (g[3] - g[1]));
      }
      if (!snap_->diverged && snap_->frame < o_.frames) sim_->step_and_wait();
      snap_ = sim_->snapshot();
    } else {
      if (snap_->diverged) paused_ = true;  // the panel says why and offers a reset
      sim_->set_playing(!paused_);
    }
    draw_frame();
    ++shown;

    if (scripted && (snap_->frame >= o_.frames || snap_->diverged)) {
      const double seconds = std::chrono::duration<double>(clock::now() - start).count();
      bool written = o_.screenshot.empty() || save_screenshot(o_.screenshot);
      const SimSnapshot& s = *snap_;
      if (carried >= 0) {
        const Vec3 offset = s.collider_offsets.at(carried), at = s.colliders.at(carried).center;
        report["carry"]["offset"] = {offset.x(), offset.y(), offset.z()};
        report["carry"]["center"] = {at.x(), at.y(), at.z()};
      }
      if (dragged >= 0) {
        const render::Ray ray = ray_at((*o_.drag)[2], (*o_.drag)[3]);
        const Vec3 x = s.state.x[dragged];
        const Vec3 target = render::drag_target(ray, grab_along_);
        const Vec3 rest = s.model->rest_position[dragged];
        report["drag"]["position"] = {x.x(), x.y(), x.z()};
        report["drag"]["ray_origin"] = {ray.origin.x(), ray.origin.y(), ray.origin.z()};
        report["drag"]["ray_direction"] = {ray.direction.x(), ray.direction.y(), ray.direction.z()};
        report["drag"]["target"] = {target.x(), target.y(), target.z()};
        report["drag"]["start"] = {rest.x(), rest.y(), rest.z()};
        std::fprintf(out_, "drag: particle %d held at (%.4f, %.4f, %.4f), %.4f m along the ray\n",
                     dragged, x.x(), x.y(), x.z(), grab_along_);
        release();
      }
      report["frames"] = s.frame;
      report["frames_shown"] = shown;
      report["wall_seconds"] = seconds;
      report["frames_per_second"] = shown / seconds;
      report["sim_ms_per_frame"] = s.step_ms;
      report["particles"] = s.model->size();
      report["diverged"] = s.diverged;
      report["renderer"] = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
      std::string report_error;
      try {
        if (!o_.report.empty()) io::write_output(o_.report, json_text(report));
      } catch (const io::OutputError& e) {
        report_error = e.what();
        written = false;
      }
      std::fprintf(out_, "%s: %lld frames in %.2f s, %.1f frames/s, simulation %.2f ms/frame\n",
                   io::shown(def_.name).c_str(), static_cast<long long>(s.frame), seconds,
                   shown / seconds, s.step_ms);
      std::fflush(out_);
      if (s.diverged)
        std::fprintf(stderr, "drape: error: diverged at frame %lld: %s\n",
                     static_cast<long long>(s.diverged_frame), s.divergence.c_str());
      if (!report_error.empty()) std::fprintf(stderr, "drape: error: %s\n", report_error.c_str());
      return !written ? kExitOutputFailed : s.diverged ? kExitDiverged : kExitOk;
    }
    glfwSwapBuffers(window_);
  }
  return kExitOk;
}

}  // namespace

int run_viewer(const ViewerOptions& options, const SceneDef& scene) {
  Viewer viewer(options, scene);
  return viewer.run();
}

}  // namespace drape::app
