// Plain definitions of a scene: what a scene file holds, with documented defaults and units.
// A definition is validated once, by check(), before anything is built from it.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "drape/material.h"
#include "drape/math.h"
#include "drape/mesh.h"

namespace drape {

/// Stiffness and damping of one kind of spring.
struct SpringParams {
  double stiffness = 0.0;  ///< N/m, >= 0
  double damping = 0.0;    ///< N·s/m along the spring, >= 0
};

enum class Orientation : uint8_t {
  vertical,   ///< hangs in the x–y plane; columns toward +x, rows toward −y
  horizontal  ///< lies in the x–z plane at height origin.y; columns toward +x, rows toward +z
};

/// One key of a motion: where the body is at time t, relative to where its definition puts it.
struct MotionKey {
  double t = 0.0;                 ///< s, from the start of the run
  Vec3 translate = Vec3::Zero();  ///< m
  Vec3 rotate = Vec3::Zero();     ///< degrees about x, then y, then z, about the pivot
};

/// A keyed rigid motion (a collider's): between keys the translation is linear and
/// the rotation a slerp; before the first key the first holds, after the last the last holds
/// unless `loop`, which repeats the keys' span. No keys: still.
struct MotionDef {
  std::vector<MotionKey> keys;  ///< times strictly increasing
  bool loop = false;            ///< repeat from the first key after the last
  bool has_pivot = false;       ///< rotate about `pivot` rather than the reference point
  Vec3 pivot = Vec3::Zero();    ///< m, in the frame the definition is written in
  bool moves() const { return !keys.empty(); }
};

enum class PinKind : uint8_t {
  grid,    ///< a grid index [col, row] (corner names are grid indices); grids only
  vertex,  ///< a vertex index, 0-based as in the OBJ file; any cloth
  box,     ///< every vertex inside an axis-aligned box at the start; any cloth
  ball     ///< every vertex inside a ball at the start (a clamp's disc); any cloth
};

/// Pinned particles. A grid index counts row 0 as the top row; a negative index counts from the
/// end (−1 is the last column or row), so {-1, 0} is the top-right corner at any resolution.
struct Pin {
  int col = 0;  ///< grid: column
  int row = 0;  ///< grid: row
  PinKind kind = PinKind::grid;
  int32_t vertex = 0;               ///< vertex: its index
  Vec3 box_min = Vec3::Zero();      ///< m, box: the corner with the smallest coordinates
  Vec3 box_max = Vec3::Zero();      ///< m, box: the opposite corner
  Vec3 ball_center = Vec3::Zero();  ///< m, ball: its centre
  double ball_radius = 0.0;         ///< m, ball: its radius, > 0
  /// Keyed motion of the pinned particles, about their centre at the start (or motion.pivot);
  /// none: they stay where they start
  MotionDef motion = {};
  static Pin at_vertex(int32_t v) {
    Pin p;
    p.kind = PinKind::vertex;
    p.vertex = v;
    return p;
  }
  static Pin in_box(const Vec3& lo, const Vec3& hi) {
    Pin p;
    p.kind = PinKind::box;
    p.box_min = lo;
    p.box_max = hi;
    return p;
  }
  static Pin in_ball(const Vec3& center, double radius) {
    Pin p;
    p.kind = PinKind::ball;
    p.ball_center = center;
    p.ball_radius = radius;
    return p;
  }
};

/// Long-range attachments (Kim et al. 2012): each free particle stays within its rest distance
/// along the cloth from each pin, times (1 + slack).
struct LongRangeDef {
  bool enabled = false;  ///< off by default
  double slack = 0.0;    ///< fraction of the rest distance allowed beyond it, in [0, 10]
};

/// Self-collision: the cloth kept from passing through itself. With it on, at the end of every
/// frame no two triangles that share no vertex cross (count_self_intersections is 0), provided
/// none did at the start.
struct SelfCollisionDef {
  bool enabled = false;  ///< off by default
  /// m, the gap kept between layers of the cloth, in (0, half the mean edge length];
  /// 0 = automatic: a quarter of the mean edge length, so it scales with the resolution
  double thickness = 0.0;
  double friction = 0.3;  ///< Coulomb coefficient between layers, >= 0
};

/// The cloth: a rectangular grid (the default), or any triangle mesh (`mesh`).
struct ClothDef {
  // The grid generator's keys (an error beside a mesh, except at their defaults).
  double width = 2.0;           ///< m, along the columns (x)
  double height = 2.0;          ///< m, along the rows
  int cols = 32;                ///< particles per row, >= 2
  int rows = 32;                ///< particles per column, >= 2
  Vec3 origin{-1.0, 2.0, 0.0};  ///< m, top-left corner (see Orientation)
  Orientation orientation = Orientation::vertical;
  // A mesh instead of the grid.
  std::shared_ptr<const ClothMesh> mesh;  ///< the shape as loaded; null: the grid
  std::string mesh_file;                  ///< where `mesh` was read from (messages, scene files)
  MeshTransform transform;                ///< places the mesh (and its rest shape)
  // Both.
  double mass = 1.0;  ///< kg, total; grid: mass / count each; mesh: shared by area
  std::vector<Pin> pins{{0, 0}, {-1, 0}};  ///< pinned particles: the grid's top corners
  SpringParams structural{2000.0, 0.5};    ///< grid: right and lower neighbours; mesh: each edge
  SpringParams shear{500.0, 0.5};          ///< grid: both diagonals of each quad; mesh: none
  /// grid: two steps right and two steps down; mesh: across each edge two triangles share,
  /// between their far vertices
  SpringParams bending{50.0, 0.1};
  /// Largest out-of-plane displacement of the start positions, as a fraction of the mean rest
  /// length of the structural springs (deterministic per particle, along the rest normal), so a
  /// symmetric cloth can fold; 0 = exactly as built. The default is 1e-4 m on the default
  /// 2 m cloth of 32 × 32 particles.
  double perturbation = 0.00155;
  LongRangeDef long_range;  ///< `false`, `true` or {"slack": s} in scene files
  /// `false`, `true` or {"thickness": m, "friction": μ} in scene files
  SelfCollisionDef self_collision;
  /// A fabric in physical units: masses, stretch and shear springs and bending elements derive
  /// from it and the mesh (see drape/material.h); `mass` and the springs are then unused (and
  /// an error in a scene file). Absent: the seed's model, as above.
  std::optional<MaterialDef> material;
};

enum class WindModel : uint8_t {
  seed,  ///< dv = c·d·|cos θ|·(dA/dm)·dt per particle, d = direction·strength (the seed's)
  aero   ///< per-triangle drag ½ρ·C·A·|u·n|(u·n)·n on the relative velocity u
};

struct WindDef {
  WindModel model = WindModel::seed;
  Vec3 direction{0.0, 0.0, 1.0};  ///< normalised on use; must not be zero when strength > 0
  double strength = 0.0;          ///< seed: wind vector length; aero: wind speed in m/s
  double coefficient = 1.0;       ///< seed: c_w; aero: drag coefficient C, >= 0
  double density = 1.225;         ///< kg/m³, air density (aero only)
  double gust = 0.0;              ///< relative amplitude of the strength's variation, in [0, 1]
  double gust_frequency = 0.5;    ///< Hz, of that variation
};

struct ForcesDef {
  Vec3 gravity{0.0, -9.81, 0.0};  ///< m/s²
  /// ρA of one particle, kg/m: dv = −(ρA/m)|v|v dt. The seed's drag: it does not scale with the
  /// particle's share of the cloth, so a finer cloth falls slower. Unset: 0.01 without
  /// cloth.material, 0 with one (see air_drag_for).
  std::optional<double> air_drag;
  /// kg/m³, air density for the drag on the cloth's area (0 = none): each particle's share A of
  /// the area moving along its normal n feels ½ρ·C·A·|v·n|(v·n) against it, so it does not
  /// change with resolution. Unset: 0 without cloth.material, 1.225 (air at sea level) with one.
  std::optional<double> air_density;
  double drag_coefficient = 1.2;  ///< C of that drag, >= 0 (a flat plate broadside: about 1.2)
  WindDef wind;

  /// The drag per particle a cloth with or without cloth.material feels: the value given, else
  /// the seed's without a material and none with one, whose cloth feels the air by its area:
  /// the seed's drag holds a fine material cloth back (at 64 cells a 5 cm strip's 0.11 mg
  /// particles cannot pass about 1 cm/s).
  double air_drag_for(bool material) const { return air_drag.value_or(material ? 0.0 : 0.01); }
  /// The air density a cloth with or without cloth.material feels: the value given, else none
  /// without a material and sea-level air with one.
  double air_density_for(bool material) const {
    return air_density.value_or(material ? 1.225 : 0.0);
  }
};

enum class ColliderType : uint8_t { sphere, plane, capsule, box, mesh };

struct ColliderDef {
  ColliderType type = ColliderType::sphere;
  Vec3 center{0.0, 0.0, 0.0};        ///< m, sphere or box centre, or a point on the plane
  double radius = 0.5;               ///< m, sphere and capsule, > 0
  Vec3 normal{0.0, 1.0, 0.0};        ///< plane only: the side the cloth stays on; normalised on use
  Vec3 a{0.0, 0.0, 0.0};             ///< m, capsule: one end of its axis
  Vec3 b{0.0, 1.0, 0.0};             ///< m, capsule: the other end (≠ a)
  Vec3 half_extents{0.5, 0.5, 0.5};  ///< m, box: half its size along its own axes, each > 0
  Vec3 rotate = Vec3::Zero();        ///< degrees, box: about x, then y, then z
  /// mesh: the triangles as loaded (closed: an inside; open: two-sided), placed by transform
  std::shared_ptr<const ClothMesh> mesh = nullptr;
  std::string mesh_file = {};    ///< mesh: where it was read from (messages, scene files)
  MeshTransform transform = {};  ///< mesh: scale, rotation, translation, as cloth.transform
  double friction = 0.3;         ///< Coulomb coefficient, >= 0
  double thickness = 0.01;       ///< m, contact offset kept between cloth and surface, >= 0
  MotionDef motion = {};         ///< none: the collider stays where it is defined
};

enum class Method : uint8_t {
  symplectic,  ///< semi-implicit Euler with automatic stable substeps (the seed's update)
  implicit,    ///< backward Euler, one Newton step per substep, filtered PCG (Baraff–Witkin)
  xpbd,        ///< extended position-based dynamics, many substeps (Macklin et al. 2016, 2019)
  fast,        ///< local/global implicit Euler on a prefactored matrix (Liu et al. 2013)
  /// "auto": chooses a method and its settings for the scene, and adapts them while it runs
  /// to keep the structural strain within solver.tolerance at the least cost
  automatic
};
/// Every method, in the order tables list them.
inline constexpr Method kAllMethods[] = {Method::symplectic, Method::implicit, Method::xpbd,
                                         Method::fast, Method::automatic};

/// The floating-point type a solver keeps the cloth in while it steps.
enum class Precision : uint8_t {
  f64,  ///< "double": every method; round-off ~1e-16 relative
  f32   ///< "single": xpbd only; half the memory traffic and twice the vector width, ~2× faster
        ///< on large cloth, round-off ~1e-7 relative (0.2 µm on a 2 m cloth)
};

struct SolverDef {
  Method method = Method::automatic;  ///< "auto" unless a scene names another
  Precision precision = Precision::f64;
  double dt = 1.0 / 60.0;    ///< s, one frame, in [1e-6, 0.1]
  int substeps = 0;          ///< per frame; 0 = automatic (the stable minimum)
  double safety = 0.9;       ///< fraction of the stability bound used by automatic substeps
  int max_substeps = 10000;  ///< automatic substeps above this are refused
  /// xpbd: constraint iterations per substep; fast: local/global iterations per substep;
  /// 0 = the method's default (xpbd 1; fast: from the Chebyshev estimate, 10..200).
  /// In [0, 10000].
  int iterations = 0;
  /// xpbd: extra Gauss–Seidel sweeps, per substep, of the stiffest springs (the structural ones
  /// in the shipped scenes) after the sweeps of all springs, in [0, 10000]; 0 = none. With
  /// line_passes, sweeps of the structural springs after the passes instead.
  int stiff_sweeps = 0;
  /// xpbd: passes, per substep, that solve each row and each column of structural springs as
  /// one chain, exactly (a tridiagonal solve), in place of sweeping them spring by spring, with
  /// the contacts and attachments before each pass; in [0, 10000]; 0 = none. A pinned cloth
  /// needs cloth.long_range with them.
  int line_passes = 0;
  /// xpbd with line_passes: the over-relaxation ω of every line pass but the last (each chain's
  /// Δλ times ω: block successive over-relaxation), in (0, 2); 1 = plain block Gauss–Seidel.
  double line_relaxation = 1.3;
  double cg_tolerance = 1e-5;    ///< implicit: CG stops at this relative residual, in (0, 1)
  int cg_max_iterations = 2000;  ///< implicit: CG iteration cap per substep, in [1, 100000]
  /// fast: spectral radius estimate for Chebyshev acceleration (Wang 2015), in [0, 1);
  /// 0 = automatic (from stiffness, mass and step).
  double chebyshev_rho = 0.0;
  /// auto: the largest structural strain |length/rest − 1| accepted, which it holds by raising
  /// and lowering its effort; in [1e-4, 1].
  double tolerance = 0.01;
};

struct SceneDef {
  std::string name = "untitled";
  ClothDef cloth;
  ForcesDef forces;
  std::vector<ColliderDef> colliders;
  SolverDef solver;
  double duration = 5.0;  ///< s, simulated by `drape run`
};

/// Names used in scene files and on the command line.
const char* to_string(Method m);
/// The method called `name`, if there is one.
std::optional<Method> method_from_string(const std::string& name);
/// Every method's name, for messages: "symplectic, implicit, ... or fast".
std::string method_names();
const char* to_string(Precision p);
const char* to_string(WindModel m);
const char* to_string(ColliderType t);
const char* to_string(Orientation o);

/// Throws InputError naming the first field that is out of range (a JSON-style path such as
/// "cloth.mass"). Types and key names are the loader's business; ranges are checked here so a
/// definition built in C++ is held to the same rules as one read from a file.
void check(const SceneDef& def);

/// How messages name the cloth's mesh: "cloth.mesh (FILE)", or "cloth.mesh" for one made in
/// code.
std::string cloth_mesh_key(const ClothDef& c);

/// Frames in a run: round(duration / dt).
int64_t frame_count(const SceneDef& def);

}  // namespace drape
