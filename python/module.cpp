// The Python module `drape`: scenes from files or dicts, a simulation stepped from Python with
// the state as NumPy views, and headless runs that return the `drape run --stats` dict.
//
// Stepping releases the GIL, so other Python threads (a Dask worker's, a GUI's) run meanwhile;
// between frames the GIL is taken back briefly to let Ctrl-C (KeyboardInterrupt) stop a long
// step() or run() at the end of the frame under way.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "drape/error.h"
#include "drape/simulation.h"
#include "io/run_stats.h"
#include "io/scene_io.h"
#include "py_json.h"

namespace drape::python {

namespace py = pybind11;
using nlohmann::json;
using clock_type = std::chrono::steady_clock;

namespace {

static_assert(sizeof(Vec3) == 3 * sizeof(double), "positions are viewed as (n, 3) doubles");
static_assert(sizeof(Triangle) == 3 * sizeof(int32_t), "triangles are viewed as (m, 3) int32");

// Messages from the scene parser name overrides as the command line has them (--set KEY); here
// they come from the overrides dict.
InputError renamed_overrides(const InputError& e) {
  std::string path = e.path();
  for (size_t at; (at = path.find("--set ")) != std::string::npos;)
    path.replace(at, 6, "override ");
  return InputError(path, e.problem());
}

// A scene from a file's path or a dict of the file's keys, with overrides {dotted key: value}.
SceneDef load(const py::object& scene, const py::dict& overrides) {
  std::vector<std::string> sets;
  for (const auto& [key, value] : overrides) {
    if (!py::isinstance<py::str>(key))
      throw InputError("overrides", "keys must be dotted scene keys as strings, got " +
                                        std::string(py::repr(key)));
    const std::string name = key.cast<std::string>();
    if (name.find('=') != std::string::npos)
      throw InputError("override " + name, "a key cannot contain \"=\"");
    sets.push_back(name + "=" + to_json(value, "override " + name).dump());
  }
  try {
    if (py::isinstance<py::dict>(scene)) {
      json j;
      try {
        j = to_json(scene, "");
      } catch (const InputError& e) {
        throw InputError("scene: " + e.path(), e.problem());
      }
      try {
        for (const std::string& s : sets) io::apply_override(j, s);
      } catch (const InputError& e) {
        throw InputError("scene: " + e.path(), e.problem());
      }
      return io::parse_scene(j, "scene");
    }
    if (py::isinstance<py::str>(scene) ||
        py::isinstance(scene, py::module_::import("os").attr("PathLike")))
      return io::load_scene(py::str(py::module_::import("os").attr("fspath")(scene)), sets);
  } catch (const InputError& e) {
    throw renamed_overrides(e);
  }
  throw py::type_error("scene: expected a scene file's path or a dict of its keys, got " +
                       std::string(py::str(py::type::handle_of(scene).attr("__qualname__"))));
}

// Raises KeyboardInterrupt (or whatever a signal handler raised) if a signal came.
void check_signals() {
  if (PyErr_CheckSignals() != 0) throw py::error_already_set();
}

// A simulation and the record of its stepping, for stats().
class PySimulation {
 public:
  explicit PySimulation(const SceneDef& def) {
    const auto t0 = clock_type::now();
    sim_.emplace(def);
    record_.setup_ms = std::chrono::duration<double, std::milli>(clock_type::now() - t0).count();
  }

  // Steps up to `frames` frames, GIL released for each, stopping at divergence; signals are
  // checked between frames.
  bool step(int64_t frames) {
    if (frames < 0) throw py::value_error("frames: must be >= 0, got " + std::to_string(frames));
    Busy busy(*this);
    for (int64_t f = 0; f < frames && !sim_->diverged(); ++f) {
      bool ok;
      {
        py::gil_scoped_release release;
        const auto t0 = clock_type::now();
        ok = sim_->step();
        const double ms = std::chrono::duration<double, std::milli>(clock_type::now() - t0).count();
        record_.frame_ms.push_back(ms);
        record_.wall_seconds += ms / 1000.0;
      }
      if (!ok) break;
      check_signals();
    }
    return !sim_->diverged();
  }

  py::dict stats() const {
    Busy busy(*this);
    io::RunResult r = record_;
    r.status = sim_->diverged() ? io::RunStatus::diverged : io::RunStatus::ok;
    r.frames = sim_->frame();
    return to_python(io::stats_json(*sim_, r));
  }

  void grab(int64_t particle) {
    Busy busy(*this);
    if (particle < 0 || particle >= sim_->model().size())
      throw py::index_error("particle " + std::to_string(particle) +
                            " is out of range: the cloth has " +
                            std::to_string(sim_->model().size()) + " particles");
    sim_->grab(static_cast<int32_t>(particle));
  }

  void move_grab(const std::vector<double>& target) {
    Busy busy(*this);
    if (target.size() != 3)
      throw py::value_error("move_grab: expected a position [x, y, z] in m, got " +
                            std::to_string(target.size()) + " numbers");
    const Vec3 x(target[0], target[1], target[2]);
    if (!x.allFinite()) throw py::value_error("move_grab: the position must be finite");
    if (sim_->grabbed() < 0)
      throw std::runtime_error("move_grab: nothing is held; grab(i) a particle first");
    sim_->move_grab(x);
  }

  void release() {
    Busy busy(*this);
    sim_->release();
  }

  const Simulation& sim() const { return *sim_; }

 private:
  // Stepping runs without the GIL, so another Python thread could call in meanwhile: calls that
  // change the simulation or read more than one figure of it are refused until the step is
  // done, rather than race it.
  struct Busy {
    explicit Busy(const PySimulation& s) : self(s) {
      if (self.busy_.exchange(true))
        throw std::runtime_error("the simulation is stepping in another thread");
    }
    ~Busy() { self.busy_ = false; }
    const PySimulation& self;
  };

  std::optional<Simulation> sim_;
  io::RunResult record_;
  mutable std::atomic<bool> busy_{false};
};

// A read-only (rows, 3) view on `data`, kept alive by `owner`.
template <typename T>
py::array view(const T* data, size_t rows, const py::object& owner) {
  const auto n = static_cast<py::ssize_t>(rows), size = static_cast<py::ssize_t>(sizeof(T));
  py::array a(py::dtype::of<T>(), {n, py::ssize_t{3}}, {3 * size, size}, data, owner);
  a.attr("setflags")(py::arg("write") = false);
  return a;
}

py::dict run(const py::object& scene, std::optional<double> seconds,
             std::optional<py::dict> overrides) {
  // A copy: the caller's dict is left as it was.
  py::dict sets = overrides ? py::dict(overrides->attr("copy")()) : py::dict();
  if (seconds) sets["duration"] = *seconds;
  const SceneDef def = load(scene, sets);
  const int64_t frames = frame_count(def);
  PySimulation sim(def);
  const auto t0 = clock_type::now();
  sim.step(frames);
  py::dict stats = sim.stats();
  stats["wall_seconds"] = std::chrono::duration<double>(clock_type::now() - t0).count();
  return stats;
}

}  // namespace

}  // namespace drape::python

PYBIND11_MODULE(drape, m) {
  using namespace drape;
  using namespace drape::python;
  m.doc() =
      "drape: a fast, stable mass-spring cloth simulator.\n\n"
      "Simulation(scene) steps a cloth from a scene file or a dict of its keys; run(scene) runs\n"
      "one headless and returns the stats that `drape run --stats` writes. Units are SI: m, s,\n"
      "kg, N/m.";
  m.attr("__version__") = DRAPE_VERSION;

  py::register_exception<InputError>(m, "InputError", PyExc_ValueError).doc() =
      "A scene or an override that drape refuses (a subclass of ValueError). The message "
      "names the file (or 'scene' for a dict), the key and the problem, as the drape "
      "command's does.";

  py::class_<PySimulation>(m, "Simulation",
                           "One cloth with its forces and colliders, advanced a frame at a time.")
      .def(py::init([](const py::object& scene) {
             const SceneDef def = load(scene, py::dict());
             return std::make_unique<PySimulation>(def);
           }),
           py::arg("scene"),
           "Builds the scene: a scene file's path, or a dict with a scene file's keys (the same "
           "defaults, checks and messages). Raises InputError on bad input.")
      .def("step", &PySimulation::step, py::arg("frames") = 1,
           "Advances `frames` frames of solver.dt seconds each. Returns False once the state has "
           "diverged (later calls then do nothing); stats() says why. Ctrl-C stops it at the end "
           "of the frame under way.")
      .def_property_readonly(
          "positions",
          [](const py::object& self) {
            const auto& x = self.cast<const PySimulation&>().sim().state().x;
            return view(reinterpret_cast<const double*>(x.data()), x.size(), self);
          },
          "Particle positions in m: a read-only float64 array (n, 3), a view on the live state "
          "(no copy; it changes as the simulation steps; copy() it to keep a frame).")
      .def_property_readonly(
          "velocities",
          [](const py::object& self) {
            const auto& v = self.cast<const PySimulation&>().sim().state().v;
            return view(reinterpret_cast<const double*>(v.data()), v.size(), self);
          },
          "Particle velocities in m/s: a read-only float64 array (n, 3), a view like positions.")
      .def_property_readonly(
          "triangles",
          [](const py::object& self) {
            const auto& t = self.cast<const PySimulation&>().sim().model().triangles;
            return view(reinterpret_cast<const int32_t*>(t.data()), t.size(), self);
          },
          "The cloth's triangles as particle indices: a read-only int32 array (m, 3), "
          "counter-clockwise seen from the front.")
      .def_property_readonly(
          "time", [](const PySimulation& s) { return s.sim().time(); }, "Simulated time in s.")
      .def_property_readonly(
          "frame", [](const PySimulation& s) { return s.sim().frame(); }, "Frames simulated.")
      .def("stats", &PySimulation::stats,
           "The stats `drape run --stats` writes, as a dict (status, frames, max_strain, ...): "
           "the stepping so far and the state now.")
      .def("grab", &PySimulation::grab, py::arg("i"),
           "Holds particle i still (the viewer's mouse drag), where it is now.")
      .def("move_grab", &PySimulation::move_grab, py::arg("xyz"),
           "Moves the held particle to xyz (m), with zero velocity.")
      .def("release", &PySimulation::release, "Lets the held particle go (with zero velocity).")
      .def("__repr__", [](const PySimulation& s) {
        return "<drape.Simulation '" + s.sim().def().name +
               "': " + std::to_string(s.sim().model().size()) + " particles, frame " +
               std::to_string(s.sim().frame()) + ">";
      });

  m.def("run", &run, py::arg("scene"), py::arg("seconds") = py::none(),
        py::arg("overrides") = py::none(),
        "Runs a scene headless, as `drape run` does, and returns its stats dict. `scene`: a "
        "file's path or a dict of its keys; `seconds` replaces its duration; `overrides` maps "
        "dotted keys to values, as `--set KEY=VALUE` ({'cloth.resolution': [64, 64]}). Raises "
        "InputError on bad input; Ctrl-C stops it at the end of the frame under way.");
}
