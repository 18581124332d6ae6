#include "render/renderer.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "io/collider_mesh.h"
#include "io/output_file.h"
#include "stb_image_write.h"

namespace drape::render {

namespace {

// Colours, linear RGB. Front and back differ in hue (warm orange, cool teal), so a fold shows
// which side faces the eye even where the shading is flat; the tests look for these hues.
constexpr glm::vec3 kFront{0.90f, 0.42f, 0.18f};
constexpr glm::vec3 kBack{0.16f, 0.62f, 0.56f};
constexpr glm::vec3 kSphere{0.78f, 0.78f, 0.76f};
constexpr glm::vec3 kWire{0.12f, 0.10f, 0.09f};
constexpr glm::vec3 kSkyTop{0.36f, 0.40f, 0.47f};
constexpr glm::vec3 kSkyBottom{0.78f, 0.79f, 0.80f};
constexpr glm::vec3 kPin{0.95f, 0.95f, 0.95f};
constexpr glm::vec3 kHighlight{1.0f, 0.86f, 0.15f};
constexpr glm::vec3 kHeld{1.0f, 1.0f, 0.55f};

constexpr const char* kSurfaceVertex = R"(#version 330 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec2 a_uv;
uniform mat4 u_model;
uniform mat3 u_normal_matrix;
uniform mat4 u_view_proj;
out vec3 v_world;
out vec3 v_normal;
out vec2 v_uv;
void main() {
  vec4 world = u_model * vec4(a_position, 1.0);
  v_world = world.xyz;
  v_normal = u_normal_matrix * a_normal;
  v_uv = a_uv;
  gl_Position = u_view_proj * world;
}
)";

// Modes: 0 cloth (two colours by facing, optional checker), 1 one lit colour, 2 ground grid,
// 3 one flat colour (wireframe).
constexpr const char* kSurfaceFragment = R"(#version 330 core
in vec3 v_world;
in vec3 v_normal;
in vec2 v_uv;
uniform int u_mode;
uniform vec3 u_front;
uniform vec3 u_back;
uniform vec3 u_color;
uniform vec3 u_eye;
uniform vec2 u_checks;
uniform vec3 u_fog;
uniform vec3 u_grid_origin;
uniform vec3 u_grid_u;
uniform vec3 u_grid_v;
out vec4 o_color;

vec3 lit(vec3 base, vec3 n, vec3 to_eye) {
  // A key light from above and in front, a weaker fill from below and behind, a headlight so
  // nothing facing the eye is black, and a sky/ground ambient term.
  vec3 key = normalize(vec3(-0.35, 0.85, 0.45));
  vec3 fill = normalize(vec3(0.5, -0.3, -0.6));
  float diffuse = 0.5 * max(dot(n, key), 0.0) + 0.2 * max(dot(n, fill), 0.0) +
                  0.35 * max(dot(n, to_eye), 0.0);
  float ambient = mix(0.22, 0.32, 0.5 + 0.5 * n.y);
  vec3 h = normalize(key + to_eye);
  float specular = 0.12 * pow(max(dot(n, h), 0.0), 32.0);
  return base * (ambient + diffuse) + vec3(specular);
}

void main() {
  vec3 to_eye = normalize(u_eye - v_world);
  vec3 n = normalize(v_normal);
  vec3 color;
  if (u_mode == 0) {
    // Both sides are lit as seen: the back face's normal is the front's, reversed.
    if (!gl_FrontFacing) n = -n;
    vec3 base = gl_FrontFacing ? u_front : u_back;
    if (u_checks.x > 0.0) {
      vec2 c = floor(v_uv * u_checks);
      base *= mod(c.x + c.y, 2.0) < 0.5 ? 1.0 : 0.8;
    }
    color = lit(base, n, to_eye);
  } else if (u_mode == 1) {
    if (dot(n, to_eye) < 0.0) n = -n;
    color = lit(u_color, n, to_eye);
  } else if (u_mode == 2) {
    vec3 d = v_world - u_grid_origin;
    vec2 g = vec2(dot(d, u_grid_u), dot(d, u_grid_v)) / 0.5;
    vec2 w = fwidth(g);
    vec2 a = abs(fract(g - 0.5) - 0.5) / max(w, vec2(1e-6));
    // Lines fade with distance before they get thinner than a pixel and shimmer.
    float line = (1.0 - min(min(a.x, a.y), 1.0)) *
                 (1.0 - smoothstep(6.0, 25.0, length(u_eye - v_world)));
    vec3 base = mix(vec3(0.64, 0.64, 0.62), vec3(0.38, 0.38, 0.38), line);
    color = lit(base, n, to_eye);
  } else {
    color = u_color;
  }
  // Distance fog into the sky colour hides the ground's far edge.
  float fog = 1.0 - exp(-max(length(u_eye - v_world) - 8.0, 0.0) / 12.0);
  o_color = vec4(mix(color, u_fog, fog), 1.0);
}
)";

constexpr const char* kLinesVertex = R"(#version 330 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_color;
uniform mat4 u_view_proj;
uniform float u_point_size;
out vec3 v_color;
void main() {
  gl_Position = u_view_proj * vec4(a_position, 1.0);
  // Overlays sit on the cloth: pull them a little toward the eye so the surface hides none.
  gl_Position.z -= 0.002 * gl_Position.w;
  gl_PointSize = u_point_size;
  v_color = a_color;
}
)";

constexpr const char* kLinesFragment = R"(#version 330 core
in vec3 v_color;
uniform int u_round;
out vec4 o_color;
void main() {
  if (u_round == 1) {
    vec2 c = 2.0 * gl_PointCoord - 1.0;
    float r = dot(c, c);
    if (r > 1.0) discard;
    o_color = vec4(r > 0.55 ? vec3(0.08) : v_color, 1.0);  // a dark rim reads on any colour
  } else {
    o_color = vec4(v_color, 1.0);
  }
}
)";

constexpr const char* kBackgroundVertex = R"(#version 330 core
out float v_height;
void main() {
  vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
  v_height = p.y;
  gl_Position = vec4(2.0 * p - 1.0, 0.0, 1.0);
}
)";

constexpr const char* kBackgroundFragment = R"(#version 330 core
in float v_height;
uniform vec3 u_top;
uniform vec3 u_bottom;
out vec4 o_color;
void main() { o_color = vec4(mix(u_bottom, u_top, clamp(v_height, 0.0, 1.0)), 1.0); }
)";

GLuint compile(GLenum type, const char* source, const char* name) {
  const GLuint shader = glCreateShader(type);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[2048] = {};
    glGetShaderInfoLog(shader, sizeof log, nullptr, log);
    glDeleteShader(shader);
    throw std::runtime_error(std::string("shader ") + name + " does not compile: " + log);
  }
  return shader;
}

GLuint link(const char* vertex, const char* fragment, const char* name) {
  const GLuint vs = compile(GL_VERTEX_SHADER, vertex, name);
  const GLuint fs = compile(GL_FRAGMENT_SHADER, fragment, name);
  const GLuint program = glCreateProgram();
  glAttachShader(program, vs);
  glAttachShader(program, fs);
  glLinkProgram(program);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint ok = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[2048] = {};
    glGetProgramInfoLog(program, sizeof log, nullptr, log);
    glDeleteProgram(program);
    throw std::runtime_error(std::string("shader ") + name + " does not link: " + log);
  }
  return program;
}

GLint loc(GLuint program, const char* name) {
  return glGetUniformLocation(program, name);
}

void set(GLuint p, const char* name, const glm::vec3& v) {
  glUniform3fv(loc(p, name), 1, &v[0]);
}
void set(GLuint p, const char* name, const glm::mat4& m) {
  glUniformMatrix4fv(loc(p, name), 1, GL_FALSE, glm::value_ptr(m));
}
void set(GLuint p, const char* name, const glm::mat3& m) {
  glUniformMatrix3fv(loc(p, name), 1, GL_FALSE, glm::value_ptr(m));
}

void attribute(GLuint index, GLuint buffer, int components) {
  glBindBuffer(GL_ARRAY_BUFFER, buffer);
  glEnableVertexAttribArray(index);
  glVertexAttribPointer(index, components, GL_FLOAT, GL_FALSE, 0, nullptr);
}

// Blue (unstrained) through green to red (at `scale` and beyond).
glm::vec3 strain_colour(double strain, double scale) {
  const float t = static_cast<float>(std::clamp(std::abs(strain) / scale, 0.0, 1.0));
  const glm::vec3 blue{0.15f, 0.35f, 1.0f}, green{0.15f, 0.9f, 0.25f}, red{1.0f, 0.12f, 0.08f};
  return t < 0.5f ? glm::mix(blue, green, 2.0f * t) : glm::mix(green, red, 2.0f * t - 1.0f);
}

void push(std::vector<float>& out, const Vec3& p, const glm::vec3& c) {
  out.insert(out.end(), {static_cast<float>(p.x()), static_cast<float>(p.y()),
                         static_cast<float>(p.z()), c.r, c.g, c.b});
}

}  // namespace

Renderer::Renderer() {
  surface_ = link(kSurfaceVertex, kSurfaceFragment, "surface");
  lines_ = link(kLinesVertex, kLinesFragment, "lines");
  background_ = link(kBackgroundVertex, kBackgroundFragment, "background");
  glGenVertexArrays(1, &empty_vao_);

  // A unit UV sphere: its positions are its normals.
  {
    constexpr int kStacks = 24, kSlices = 48;
    std::vector<float> p;
    std::vector<GLuint> idx;
    for (int i = 0; i <= kStacks; ++i) {
      const double phi = M_PI * i / kStacks;
      for (int j = 0; j <= kSlices; ++j) {
        const double theta = 2.0 * M_PI * j / kSlices;
        p.insert(p.end(), {static_cast<float>(std::sin(phi) * std::cos(theta)),
                           static_cast<float>(std::cos(phi)),
                           static_cast<float>(std::sin(phi) * std::sin(theta))});
      }
    }
    for (int i = 0; i < kStacks; ++i) {
      for (int j = 0; j < kSlices; ++j) {
        const GLuint a = i * (kSlices + 1) + j, b = a + kSlices + 1;
        idx.insert(idx.end(), {a, b, a + 1, a + 1, b, b + 1});
      }
    }
    glGenVertexArrays(1, &sphere_.vao);
    glBindVertexArray(sphere_.vao);
    glGenBuffers(1, &sphere_.position);
    glBindBuffer(GL_ARRAY_BUFFER, sphere_.position);
    glBufferData(GL_ARRAY_BUFFER, p.size() * sizeof(float), p.data(), GL_STATIC_DRAW);
    attribute(0, sphere_.position, 3);
    attribute(1, sphere_.position, 3);
    glVertexAttrib2f(2, 0.0f, 0.0f);
    glGenBuffers(1, &sphere_.index);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, sphere_.index);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, idx.size() * sizeof(GLuint), idx.data(), GL_STATIC_DRAW);
    sphere_.count = static_cast<GLsizei>(idx.size());
  }
  // The unit square [−1, 1]² in the x–z plane, normal +y: a ground plane once transformed.
  {
    const float p[] = {-1, 0, -1, 1, 0, -1, 1, 0, 1, -1, 0, 1};
    const float n[] = {0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0};
    const GLuint idx[] = {0, 2, 1, 0, 3, 2};
    glGenVertexArrays(1, &ground_.vao);
    glBindVertexArray(ground_.vao);
    glGenBuffers(1, &ground_.position);
    glBindBuffer(GL_ARRAY_BUFFER, ground_.position);
    glBufferData(GL_ARRAY_BUFFER, sizeof p, p, GL_STATIC_DRAW);
    attribute(0, ground_.position, 3);
    glGenBuffers(1, &ground_.normal);
    glBindBuffer(GL_ARRAY_BUFFER, ground_.normal);
    glBufferData(GL_ARRAY_BUFFER, sizeof n, n, GL_STATIC_DRAW);
    attribute(1, ground_.normal, 3);
    glVertexAttrib2f(2, 0.0f, 0.0f);
    glGenBuffers(1, &ground_.index);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ground_.index);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, sizeof idx, idx, GL_STATIC_DRAW);
    ground_.count = 6;
  }
  // The cloth's buffers; filled by update().
  glGenVertexArrays(1, &cloth_.vao);
  glBindVertexArray(cloth_.vao);
  glGenBuffers(1, &cloth_.position);
  glGenBuffers(1, &cloth_.normal);
  glGenBuffers(1, &cloth_.uv);
  glGenBuffers(1, &cloth_.index);
  attribute(0, cloth_.position, 3);
  attribute(1, cloth_.normal, 3);
  attribute(2, cloth_.uv, 2);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, cloth_.index);
  // Lines and points: position and colour interleaved.
  glGenVertexArrays(1, &line_vao_);
  glBindVertexArray(line_vao_);
  glGenBuffers(1, &line_vbo_);
  glBindBuffer(GL_ARRAY_BUFFER, line_vbo_);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float),
                        reinterpret_cast<const void*>(3 * sizeof(float)));
  glBindVertexArray(0);
}

Renderer::~Renderer() {
  for (Mesh* m : {&cloth_, &sphere_, &ground_, &shape_}) delete_mesh(*m);
  for (auto& [shape, m] : meshes_) delete_mesh(m);
  glDeleteBuffers(1, &line_vbo_);
  glDeleteVertexArrays(1, &line_vao_);
  glDeleteVertexArrays(1, &empty_vao_);
  glDeleteProgram(surface_);
  glDeleteProgram(lines_);
  glDeleteProgram(background_);
}

bool Renderer::update(const ClothModel& model, const ClothState& state) {
  const size_t n = state.x.size();
  for (size_t i = 0; i < n; ++i)
    if (!state.x[i].allFinite() || !state.normal[i].allFinite()) return false;
  positions_.resize(3 * n);
  normals_.resize(3 * n);
  for (size_t i = 0; i < n; ++i) {
    for (int k = 0; k < 3; ++k) {
      positions_[3 * i + k] = static_cast<float>(state.x[i][k]);
      normals_[3 * i + k] = static_cast<float>(state.normal[i][k]);
    }
  }
  x_ = state.x;
  pinned_ = state.pinned;

  glBindVertexArray(cloth_.vao);
  if (model.id != uploaded_model_) {
    std::vector<float> uv;
    uv.reserve(2 * model.uv.size());
    for (const Vec2& t : model.uv) uv.insert(uv.end(), {float(t.x()), float(t.y())});
    glBindBuffer(GL_ARRAY_BUFFER, cloth_.uv);
    glBufferData(GL_ARRAY_BUFFER, uv.size() * sizeof(float), uv.data(), GL_STATIC_DRAW);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, model.triangles.size() * sizeof(Triangle),
                 model.triangles.data(), GL_STATIC_DRAW);
    cloth_.count = static_cast<GLsizei>(3 * model.triangles.size());
    uploaded_model_ = model.id;
  }
  glBindBuffer(GL_ARRAY_BUFFER, cloth_.position);
  glBufferData(GL_ARRAY_BUFFER, positions_.size() * sizeof(float), positions_.data(),
               GL_STREAM_DRAW);
  glBindBuffer(GL_ARRAY_BUFFER, cloth_.normal);
  glBufferData(GL_ARRAY_BUFFER, normals_.size() * sizeof(float), normals_.data(), GL_STREAM_DRAW);
  glBindVertexArray(0);
  return true;
}

void Renderer::draw_lines(const std::vector<float>& data, GLenum mode, const glm::mat4& view_proj,
                          float point_size) {
  if (data.empty()) return;
  glUseProgram(lines_);
  set(lines_, "u_view_proj", view_proj);
  glUniform1f(loc(lines_, "u_point_size"), point_size);
  glUniform1i(loc(lines_, "u_round"), mode == GL_POINTS ? 1 : 0);
  glBindVertexArray(line_vao_);
  glBindBuffer(GL_ARRAY_BUFFER, line_vbo_);
  glBufferData(GL_ARRAY_BUFFER, data.size() * sizeof(float), data.data(), GL_STREAM_DRAW);
  glDrawArrays(mode, 0, static_cast<GLsizei>(data.size() / 6));
}

// A capsule, box or mesh collider, lit like a sphere. A mesh's triangles are uploaded once (in
// the frame of its definition) and placed by its pose; a capsule's or box's few hundred
// vertices are built where they are now and uploaded each time.
void Renderer::delete_mesh(Mesh& m) {
  const GLuint buffers[] = {m.position, m.normal, m.uv, m.index};
  glDeleteBuffers(4, buffers);
  glDeleteVertexArrays(1, &m.vao);
  m = Mesh{};
}

void Renderer::draw_shape(const Collider& c) {
  Mesh* mesh = &shape_;
  glm::mat4 model(1.0f);
  glm::mat3 normal_matrix(1.0f);
  auto upload = [](Mesh& m, const io::SurfaceMesh& s) {
    if (m.vao == 0) {
      glGenVertexArrays(1, &m.vao);
      glBindVertexArray(m.vao);
      glGenBuffers(1, &m.position);
      glGenBuffers(1, &m.normal);
      glGenBuffers(1, &m.index);
      attribute(0, m.position, 3);
      attribute(1, m.normal, 3);
    }
    std::vector<float> p, n;
    for (size_t k = 0; k < s.position.size(); ++k)
      for (int d = 0; d < 3; ++d) {
        p.push_back(static_cast<float>(s.position[k][d]));
        n.push_back(static_cast<float>(s.normal[k][d]));
      }
    std::vector<GLuint> idx;
    for (const auto& t : s.triangles)
      idx.insert(idx.end(), {GLuint(t[0]), GLuint(t[1]), GLuint(t[2])});
    glBindVertexArray(m.vao);
    glBindBuffer(GL_ARRAY_BUFFER, m.position);
    glBufferData(GL_ARRAY_BUFFER, p.size() * sizeof(float), p.data(), GL_DYNAMIC_DRAW);
    glBindBuffer(GL_ARRAY_BUFFER, m.normal);
    glBufferData(GL_ARRAY_BUFFER, n.size() * sizeof(float), n.data(), GL_DYNAMIC_DRAW);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, m.index);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, idx.size() * sizeof(GLuint), idx.data(), GL_DYNAMIC_DRAW);
    m.count = static_cast<GLsizei>(idx.size());
  };
  if (c.type == ColliderType::mesh) {
    auto it = std::find_if(meshes_.begin(), meshes_.end(),
                           [&](const auto& e) { return e.first == c.mesh; });
    if (it == meshes_.end()) {
      meshes_.push_back({c.mesh, Mesh{}});
      it = meshes_.end() - 1;
      upload(it->second, io::triangle_mesh(c, false));
    }
    mesh = &it->second;
    const Mat3& R = c.pose.rotation;
    for (int col = 0; col < 3; ++col) {
      for (int row = 0; row < 3; ++row) {
        model[col][row] = static_cast<float>(R(row, col));
        normal_matrix[col][row] = static_cast<float>(R(row, col));
      }
      model[3][col] = static_cast<float>(c.pose.translation[col]);
    }
  } else {
    upload(shape_, io::collider_mesh(c, c.center, 1.0));
  }
  set(surface_, "u_model", model);
  set(surface_, "u_normal_matrix", normal_matrix);
  glUniform1i(loc(surface_, "u_mode"), 1);
  set(surface_, "u_color", kSphere);
  glBindVertexArray(mesh->vao);
  glDrawElements(GL_TRIANGLES, mesh->count, GL_UNSIGNED_INT, nullptr);
}

void Renderer::draw(const OrbitCamera& camera, const PixelRect& rect, const ClothModel& model,
                    const std::vector<Collider>& colliders, const DrawOptions& options) {
  glViewport(rect.x, rect.y, rect.width, rect.height);
  glEnable(GL_SCISSOR_TEST);
  glScissor(rect.x, rect.y, rect.width, rect.height);
  glDisable(GL_CULL_FACE);
  glDisable(GL_BLEND);
  glEnable(GL_PROGRAM_POINT_SIZE);  // markers set their size in the shader
  glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
  glClear(GL_DEPTH_BUFFER_BIT);

  // Sky.
  glDisable(GL_DEPTH_TEST);
  glUseProgram(background_);
  set(background_, "u_top", kSkyTop);
  set(background_, "u_bottom", kSkyBottom);
  glBindVertexArray(empty_vao_);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LEQUAL);

  const double aspect = static_cast<double>(rect.width) / std::max(rect.height, 1);
  const glm::mat4 view_proj = glm::mat4(camera.projection(aspect) * camera.view());
  const glm::vec3 eye = glm::vec3(camera.eye());
  glUseProgram(surface_);
  set(surface_, "u_view_proj", view_proj);
  set(surface_, "u_eye", eye);
  set(surface_, "u_fog", 0.5f * (kSkyTop + kSkyBottom));

  // Colliders. Mesh colliders no longer drawn (a new scene, a changed definition) let go.
  for (auto it = meshes_.begin(); it != meshes_.end();) {
    const bool drawn = std::any_of(colliders.begin(), colliders.end(),
                                   [&](const Collider& c) { return c.mesh == it->first; });
    if (drawn) {
      ++it;
    } else {
      delete_mesh(it->second);
      it = meshes_.erase(it);
    }
  }
  for (const Collider& c : colliders) {
    const glm::vec3 centre(c.center.x(), c.center.y(), c.center.z());
    if (c.type == ColliderType::sphere) {
      const glm::mat4 m = glm::scale(glm::translate(glm::mat4(1.0f), centre),
                                     glm::vec3(static_cast<float>(c.radius)));
      set(surface_, "u_model", m);
      set(surface_, "u_normal_matrix", glm::mat3(1.0f));
      glUniform1i(loc(surface_, "u_mode"), 1);
      set(surface_, "u_color", kSphere);
      glBindVertexArray(sphere_.vao);
      glDrawElements(GL_TRIANGLES, sphere_.count, GL_UNSIGNED_INT, nullptr);
    } else if (c.type != ColliderType::plane) {
      draw_shape(c);
    } else {
      const glm::vec3 n = glm::normalize(glm::vec3(c.normal.x(), c.normal.y(), c.normal.z()));
      const glm::vec3 helper = std::abs(n.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 0, 1);
      const glm::vec3 u = glm::normalize(glm::cross(helper, n));
      const glm::vec3 v = glm::cross(n, u);
      constexpr float kHalf = 60.0f;  // m: far enough for the fog to hide the edge
      glm::mat4 m(1.0f);
      m[0] = glm::vec4(kHalf * u, 0.0f);
      m[1] = glm::vec4(n, 0.0f);
      m[2] = glm::vec4(kHalf * v, 0.0f);
      m[3] = glm::vec4(centre, 1.0f);
      set(surface_, "u_model", m);
      set(surface_, "u_normal_matrix", glm::mat3(u, n, v));
      glUniform1i(loc(surface_, "u_mode"), 2);
      set(surface_, "u_grid_origin", centre);
      set(surface_, "u_grid_u", u);
      set(surface_, "u_grid_v", v);
      glBindVertexArray(ground_.vao);
      glDrawElements(GL_TRIANGLES, ground_.count, GL_UNSIGNED_INT, nullptr);
    }
  }

  // The cloth; pushed back a little when its edges are drawn over it.
  const bool have_cloth = cloth_.count > 0 && x_.size() == static_cast<size_t>(model.size());
  if (have_cloth) {
    set(surface_, "u_model", glm::mat4(1.0f));
    set(surface_, "u_normal_matrix", glm::mat3(1.0f));
    glUniform1i(loc(surface_, "u_mode"), 0);
    set(surface_, "u_front", kFront);
    set(surface_, "u_back", kBack);
    // Square checks about an eighth of the cloth's width across.
    const float checks_u = options.checker ? 8.0f : 0.0f;
    // As many along v as keep them square: a grid's rows against its columns; a mesh's uv is
    // scaled alike on both axes already.
    const float checks_v =
        model.grid.present()
            ? checks_u * static_cast<float>(model.grid.rows - 1) / std::max(model.grid.cols - 1, 1)
            : checks_u;
    glUniform2f(loc(surface_, "u_checks"), checks_u, std::max(1.0f, std::round(checks_v)));
    glBindVertexArray(cloth_.vao);
    if (options.wireframe) {
      glEnable(GL_POLYGON_OFFSET_FILL);
      glPolygonOffset(1.0f, 1.0f);
    }
    glDrawElements(GL_TRIANGLES, cloth_.count, GL_UNSIGNED_INT, nullptr);
    glDisable(GL_POLYGON_OFFSET_FILL);
    if (options.wireframe) {
      glUniform1i(loc(surface_, "u_mode"), 3);
      set(surface_, "u_color", kWire);
      glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
      glDrawElements(GL_TRIANGLES, cloth_.count, GL_UNSIGNED_INT, nullptr);
      glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    }
  }

  if (have_cloth && options.springs) {
    line_data_.clear();
    for (const Spring& s : model.springs) {
      if (!(options.spring_kinds & (1u << static_cast<int>(s.kind)))) continue;
      const double strain = (x_[s.j] - x_[s.i]).norm() / s.rest - 1.0;
      const glm::vec3 c = strain_colour(strain, options.strain_scale);
      push(line_data_, x_[s.i], c);
      push(line_data_, x_[s.j], c);
    }
    draw_lines(line_data_, GL_LINES, view_proj, 1.0f);
  }

  if (have_cloth) {
    // Markers keep their size in pixels: a fixed fraction of the viewport's height.
    const float size = std::clamp(rect.height / 70.0f, 6.0f, 16.0f);
    line_data_.clear();
    if (options.pins)
      for (size_t i = 0; i < x_.size(); ++i)
        if (pinned_[i]) push(line_data_, x_[i], kPin);
    // A few pins are markers; a pinned region (a clamp holding hundreds of particles) would hide
    // the cloth under full-size dots, so it is dotted finely.
    const bool region = line_data_.size() > 64 * 6;  // six floats (position, colour) a point
    draw_lines(line_data_, GL_POINTS, view_proj, region ? std::max(2.0f, 0.3f * size) : size);
    // The cursor's particle stays visible behind folds: the hand is on it.
    line_data_.clear();
    const int32_t mark = options.held >= 0 ? options.held : options.highlighted;
    if (mark >= 0 && mark < static_cast<int32_t>(x_.size()))
      push(line_data_, x_[mark], options.held >= 0 ? kHeld : kHighlight);
    glDisable(GL_DEPTH_TEST);
    draw_lines(line_data_, GL_POINTS, view_proj, 1.6f * size);
    glEnable(GL_DEPTH_TEST);
  }

  glBindVertexArray(0);
  glUseProgram(0);
  glDisable(GL_SCISSOR_TEST);
}

std::vector<uint8_t> read_pixels(const PixelRect& rect) {
  std::vector<uint8_t> raw(static_cast<size_t>(rect.width) * rect.height * 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(rect.x, rect.y, rect.width, rect.height, GL_RGBA, GL_UNSIGNED_BYTE, raw.data());
  // OpenGL's rows run bottom to top; images' top to bottom. The window's alpha is meaningless.
  std::vector<uint8_t> out(raw.size());
  const size_t row = static_cast<size_t>(rect.width) * 4;
  for (int y = 0; y < rect.height; ++y)
    std::copy_n(raw.data() + (rect.height - 1 - y) * row, row, out.data() + y * row);
  for (size_t i = 3; i < out.size(); i += 4) out[i] = 255;
  return out;
}

void write_png(const std::string& file, int width, int height, const std::vector<uint8_t>& rgba) {
  // RGB: the alpha channel is opaque everywhere, and leaving it out keeps the files small.
  std::vector<uint8_t> rgb(rgba.size() / 4 * 3);
  for (size_t i = 0, j = 0; i < rgba.size(); i += 4, j += 3) std::copy_n(&rgba[i], 3, &rgb[j]);
  io::OutputFile out(file);
  auto write = [](void* f, void* data, int size) {
    std::fwrite(data, 1, static_cast<size_t>(size), static_cast<FILE*>(f));
  };
  if (!stbi_write_png_to_func(write, out.get(), width, height, 3, rgb.data(), width * 3))
    throw io::OutputError(file + ": cannot encode the PNG picture");
  out.commit();
}

}  // namespace drape::render
