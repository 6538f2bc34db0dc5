// The Python module `sluice`: cases, simulations stepped from Python with the particles as numpy
// arrays, runs with the outputs of `sluice run`, and pictures of frames. The C++ here is the part
// that touches the solver; the rest of the module is Python (sluice_module.py, built in), run in the
// module's namespace when it is imported.
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>
#include <pybind11/eval.h>

#include <fmt/format.h>
#include <omp.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "sluice/case/builtin_cases.hpp"
#include "sluice/case/case_error.hpp"
#include "sluice/case/load.hpp"
#include "sluice/case/overrides.hpp"
#include "sluice/io/atomic_file.hpp"
#include "sluice/io/checkpoint.hpp"
#include "sluice/io/frames.hpp"
#include "sluice/io/npz.hpp"
#include "sluice/io/runner.hpp"
#include "sluice/mpi/mpi_communicator.hpp"
#include "sluice/physics/simd_target.hpp"
#include "sluice/render/options.hpp"
#include "sluice/render/render.hpp"
#include "sluice/render/render_error.hpp"
#include "sluice_module_py.hpp"

namespace py = pybind11;
namespace fs = std::filesystem;

namespace sluice::python {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// A built-in case's name, or a case file's path (a file of that name wins over a built-in case, a
// directory does not: as `sluice run` reads its argument).
Case load_case_argument(const std::string& name_or_path) {
  std::error_code ec;
  if (!fs::exists(name_or_path, ec) || fs::is_directory(name_or_path, ec)) {
    if (auto c = load_builtin_case(name_or_path)) return *c;
    if (name_or_path.find('/') == std::string::npos && !name_or_path.ends_with(".toml"))
      throw CaseError(fmt::format("'{}' is neither a built-in case (sluice.cases() lists them) nor a case file",
                                  name_or_path));
  }
  return load_case_file(name_or_path);
}

Case with_overrides(const Case& c, const std::vector<std::string>& assignments) {
  Case changed = c;
  apply_overrides(changed, assignments);
  return changed;
}

// A frame's fields as numpy arrays (copies), under the .npz frames' names.
py::dict frame_arrays(const Frame& frame) {
  py::dict out;
  const auto n = static_cast<py::ssize_t>(frame.size());
  for (const FrameField& field : frame.fields) {
    std::visit(
        [&](const auto& values) {
          using T = typename std::decay_t<decltype(values)>::value_type;
          std::vector<py::ssize_t> shape{n};
          if (field.vector) shape.push_back(frame.dimension);
          py::array_t<T> a(shape);
          std::copy(values.begin(), values.end(), a.mutable_data());
          out[py::str(field.short_name)] = std::move(a);
        },
        field.values);
  }
  return out;
}

// The processes of an interpreter run under mpirun, once mpi4py has started MPI (null for one
// process). Dropped at the interpreter's exit, before mpi4py stops MPI.
std::unique_ptr<MpiCommunicator>& world() {
  static std::unique_ptr<MpiCommunicator> w;
  return w;
}

void start_world() {
  if (world()) return;
  world() = world_of_started_mpi();
  if (world()) py::module_::import("atexit").attr("register")(py::cpp_function([] { world().reset(); }));
}

// An error raised by Python code the solver called (the body force): kept to be raised again once
// the step has been undone. Not a std::runtime_error, so that the run reports it as a failure of the
// step rather than an instability.
struct PythonCallbackError : std::exception {
  const char* what() const noexcept override { return "a Python function given to the simulation raised an error"; }
};

class PySimulation {
 public:
  PySimulation(const std::optional<Case>& c, int threads, std::optional<fs::path> output_dir, std::optional<fs::path> restart)
      {
    if (threads < 1) throw py::value_error(fmt::format("threads = {}: expected 1 or more", threads));
    RunOptions options;
    options.threads = threads;
    options.progress = RunOptions::Progress::none;
    options.stop_requested = &stop_;
    options.command = "python3 (import sluice)";
    options.comm = world().get();
    comm_ = options.comm;
    if (restart) {
      options.restart = *restart;
      options.output_dir = output_dir ? *output_dir : restart->parent_path();
      if (options.output_dir.empty()) options.output_dir = ".";
    } else if (output_dir) {
      options.output_dir = *output_dir;
    }
    py::gil_scoped_release release;
    runner_ = std::make_unique<Runner>(c ? *c : Case{}, options, log_);
    dimension_ = runner_->simulation().dimension();
  }

  Runner& runner() {
    if (!runner_) throw std::logic_error("the simulation is closed");
    return *runner_;
  }
  const Simulation& sim() { return runner().simulation(); }

  // Steps while fewer than max_steps were taken and the time is before stop_at, cut_at and the end;
  // a step that would pass cut_at ends on it. Returns after wall_limit seconds too. Ctrl-C between
  // steps raises KeyboardInterrupt (after saving the state, when the run writes outputs).
  std::int64_t advance(std::int64_t max_steps, double stop_at, double cut_at, double wall_limit) {
    Runner& r = runner();
    if (r.stopped()) throw std::logic_error("the run has finished or stopped; no more steps can be taken");
    const auto start = std::chrono::steady_clock::now();
    const double target = std::min({stop_at, cut_at, r.end_time()});
    std::int64_t taken = 0;
    while (taken < max_steps && r.simulation().time() < target) {
      bool stepped = false;
      try {
        py::gil_scoped_release release;
        stepped = r.step(cut_at);
      } catch (const std::exception&) {
        raise_callback_error();
        throw;
      }
      if (!stepped) {
        if (r.stopped() && comm_ != nullptr) stopped_by_signal();
        break;
      }
      ++taken;
      if (PyErr_CheckSignals() != 0) {
        if (comm_ == nullptr) {
          interrupted();
          throw py::error_already_set();
        }
        // Several processes stop after the same step: the next step's start asks them all (Runner).
        pending_interrupt_.emplace();
        stop_ = true;
      }
      if (std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() >= wall_limit) break;
    }
    return taken;
  }

  // Ctrl-C: a run that writes outputs saves its state (the last frame, a checkpoint, the summary) and
  // stops, as `sluice run` does; one without outputs keeps its state and can step on.
  void interrupted() {
    if (!runner_ || !runner_->writes_outputs() || runner_->stopped()) return;
    stop_ = true;
    PyObject *type, *value, *trace;
    PyErr_Fetch(&type, &value, &trace);  // the KeyboardInterrupt, raised again after the state is saved
    try {
      py::gil_scoped_release release;
      runner_->step();  // does not step: records the stop
      result_ = runner_->finish();
    } catch (...) {
    }
    PyErr_Restore(type, value, trace);
  }

  // Under MPI, after every process stopped on a signal that reached any of them: the state saved,
  // and KeyboardInterrupt raised on every process.
  [[noreturn]] void stopped_by_signal() {
    if (runner_->writes_outputs() && !result_) {
      py::gil_scoped_release release;
      result_ = runner_->finish();
    }
    if (pending_interrupt_) {
      py::error_already_set e = std::move(*pending_interrupt_);
      pending_interrupt_.reset();
      throw e;
    }
    PyErr_SetNone(PyExc_KeyboardInterrupt);
    throw py::error_already_set();
  }

  void raise_callback_error() {
    if (!callback_error_) return;
    py::error_already_set e = std::move(*callback_error_);
    callback_error_.reset();
    throw e;
  }

  // This process's particles (all of them with one process).
  py::dict particles() { return frame_arrays(make_process_frame(sim())); }

  // Every process's particles on the root process, None on the others. Collective.
  py::object gather_particles() {
    Frame frame;
    {
      py::gil_scoped_release release;
      frame = make_frame(sim());
    }
    if (!sim().is_root()) return py::none();
    return frame_arrays(frame);
  }

  std::size_t set_velocities(const py::array& ids, const py::array& velocity) {
    if (ids.ndim() != 1 || (ids.dtype().kind() != 'i' && ids.dtype().kind() != 'u'))
      throw py::value_error(fmt::format("ids: an array of {} dimension(s) of dtype {}; expected a 1-D array of "
                                        "integer particle ids",
                                        ids.ndim(), std::string(py::str(ids.dtype()))));
    const auto n = static_cast<std::size_t>(ids.shape(0));
    if (velocity.ndim() != 2 || static_cast<std::size_t>(velocity.shape(0)) != n || velocity.shape(1) != dimension_ ||
        (velocity.dtype().kind() != 'f' && velocity.dtype().kind() != 'i'))
      throw py::value_error(fmt::format(
          "velocities: an array of shape {} and dtype {}; expected shape ({}, {}) of numbers: a row of {} "
          "components (m/s) for each of the {} ids",
          std::string(py::str(py::tuple(py::cast(std::vector<py::ssize_t>(velocity.shape(),
                                                                           velocity.shape() + velocity.ndim()))))),
          std::string(py::str(velocity.dtype())), n, dimension_, dimension_, n));
    auto id_values = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(ids);
    auto v = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(velocity);
    std::vector<std::uint32_t> id32(n);
    for (std::size_t k = 0; k < n; ++k) {
      const std::int64_t id = id_values.data()[k];
      if (id < 0 || id > std::numeric_limits<std::uint32_t>::max())
        throw py::value_error(fmt::format("ids: {} is no particle id (ids are 0 or more)", id));
      id32[k] = static_cast<std::uint32_t>(id);
    }
    const std::span<const double> values(v.data(), n * static_cast<std::size_t>(dimension_));
    if (runner().stopped()) throw std::logic_error("the run has finished or stopped; its state can no longer change");
    return runner().simulation().visit([&](auto& solver) { return solver.set_fluid_velocities(id32, values); });
  }

  // f(x, t) -> accelerations (m/s^2) of the fluid particles at x (N x dimension), or one vector for all.
  void set_body_force(const py::object& f) {
    if (f.is_none()) {
      runner().simulation().visit([](auto& solver) { solver.set_external_acceleration({}); });
      return;
    }
    if (!PyCallable_Check(f.ptr()))
      throw py::type_error("set_body_force: expected a function f(x, t) of the positions (N x dimension) and the "
                           "time, or None");
    const int dim = dimension_;
    auto hook = [this, f, dim](double t, std::size_t n, const double* x, double* a) {
      py::gil_scoped_acquire gil;
      try {
        py::array_t<double> positions({static_cast<py::ssize_t>(n), static_cast<py::ssize_t>(dim)});
        std::copy(x, x + n * static_cast<std::size_t>(dim), positions.mutable_data());
        py::object result = f(positions, t);
        py::array values = py::array::ensure(result);
        if (!values || (values.dtype().kind() != 'f' && values.dtype().kind() != 'i'))
          throw py::type_error(fmt::format("the body force returned {}; expected an array of numbers",
                                           std::string(py::repr(result))));
        auto numbers = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(values);
        const bool one = numbers.ndim() == 1 && numbers.shape(0) == dim;
        const bool each = numbers.ndim() == 2 && static_cast<std::size_t>(numbers.shape(0)) == n &&
                          numbers.shape(1) == dim;
        if (!one && !each)
          throw py::value_error(fmt::format(
              "the body force returned an array of shape {}; expected ({}, {}) (one acceleration per fluid "
              "particle) or ({},) (the same for all)",
              std::string(py::str(py::tuple(py::cast(std::vector<py::ssize_t>(numbers.shape(),
                                                                               numbers.shape() + numbers.ndim()))))),
              n, dim, dim));
        const double* src = numbers.data();
        for (std::size_t k = 0; k < n; ++k)
          for (int d = 0; d < dim; ++d) a[k * dim + d] = one ? src[d] : src[k * dim + d];
      } catch (py::error_already_set& e) {
        callback_error_.emplace(std::move(e));
        throw PythonCallbackError();
      } catch (const py::builtin_exception& e) {
        e.set_error();
        callback_error_.emplace();
        throw PythonCallbackError();
      }
    };
    runner().simulation().visit([&](auto& solver) { solver.set_external_acceleration(hook); });
  }

  py::dict diagnostics() {
    const Diagnostics d = sim().diagnostics();
    py::dict out;
    out["time"] = d.time;
    out["step"] = d.step;
    out["dt"] = d.dt;
    out["fluid_particles"] = d.fluid_particles;
    out["wall_particles"] = d.wall_particles;
    out["max_speed"] = d.max_speed;
    out["min_density"] = d.min_density;
    out["max_density"] = d.max_density;
    out["kinetic_energy"] = d.kinetic_energy;
    out["potential_energy"] = d.potential_energy;
    out["total_mass"] = d.total_mass;
    out["leaks"] = d.leaks;
    out["outflow"] = d.outflow;
    out["min_particle_distance"] = d.min_particle_distance;
    return out;
  }

  py::dict finish() {
    if (!result_) {
      py::gil_scoped_release release;
      result_ = runner().finish();
    }
    const RunResult& r = *result_;
    py::dict out;
    out["case"] = r.case_name;
    out["time"] = r.final.time;
    out["steps"] = r.final.step;
    out["steps_this_run"] = r.steps_this_run;
    out["particles"] = r.particles;
    out["wall_seconds"] = r.wall_seconds;
    out["loop_seconds"] = r.loop_seconds;
    out["particle_steps_per_second"] = r.particle_steps_per_second;
    out["frames_written"] = r.frames_written;
    out["interrupted"] = r.interrupted;
    out["output_dir"] = r.output_dir.empty() ? py::object(py::none()) : py::object(py::str(r.output_dir.string()));
    out["summary"] = format_summary(r);
    return out;
  }

  void close() {
    callback_error_.reset();
    runner_.reset();  // releases the output directory's lock
  }

  [[nodiscard]] bool closed() const { return !runner_; }
  [[nodiscard]] int rank() const { return comm_ != nullptr ? comm_->rank() : 0; }
  [[nodiscard]] int processes() const { return comm_ != nullptr ? comm_->size() : 1; }
  [[nodiscard]] int dimension() const { return dimension_; }
  [[nodiscard]] bool has_result() const { return result_.has_value(); }

 private:
  std::ostringstream log_;
  std::atomic<bool> stop_{false};
  std::unique_ptr<Runner> runner_;
  std::optional<RunResult> result_;
  std::optional<py::error_already_set> callback_error_;
  std::optional<py::error_already_set> pending_interrupt_;
  const Communicator* comm_ = nullptr;
  int dimension_ = 2;
};

// A picture of frame files: the frame of run_dir nearest `time` (the last without one), as PNG bytes.
py::bytes render_png(const fs::path& run_dir, const std::string& field, std::optional<double> time, int width,
                     int height, std::optional<std::pair<double, double>> range) {
  render::RenderOptions o;
  o.field = render::parse_field(field);
  o.format = render::Format::png;
  o.width = width;
  o.height = height;
  if (range) o.range = render::Range{range->first, range->second};
  if (time) o.times = {*time};
  const fs::path out = fs::temp_directory_path() / fmt::format("sluice-render-{}-{}.png", ::getpid(),
                                                                 std::chrono::steady_clock::now().time_since_epoch().count());
  o.output = out;
  std::string bytes;
  {
    py::gil_scoped_release release;
    if (!time) {
      // The last frame: its time, from the frame files' names in order.
      std::vector<fs::path> frames;
      for (const auto& e : fs::directory_iterator(run_dir / output_files::frames_dir))
        if (e.path().extension() == ".npz") frames.push_back(e.path());
      if (frames.empty()) throw IoError(fmt::format("{}: no frames to draw", run_dir.string()));
      std::sort(frames.begin(), frames.end());
      o.times = {read_npz_frame(frames.back()).time};
    }
    render::render_run(run_dir, o);
    bytes = read_file(out);
    std::error_code ec;
    fs::remove(out, ec);
  }
  return py::bytes(bytes);
}

// The state now as a run directory of one frame, to be drawn.
void write_state_frame(PySimulation& s, const fs::path& dir) {
  const Frame frame = make_frame(s.sim());
  fs::create_directories(dir / output_files::frames_dir);
  write_file_atomic(dir / output_files::frames_dir / "frame_000000.npz", frame_to_npz(frame));
}

}  // namespace

}  // namespace sluice::python

PYBIND11_MODULE(sluice, m) {
  using namespace sluice;
  using namespace sluice::python;
  m.doc() = "sluice: SPH for free-surface water flows (https://github.com/ - see the documentation's Python page)";
  m.attr("__version__") = SLUICE_VERSION;

  static py::exception<CaseError> case_error(m, "CaseError", PyExc_ValueError);
  static py::exception<IoError> output_error(m, "OutputError", PyExc_OSError);
  static py::exception<FormatError> format_error(m, "FormatError", PyExc_ValueError);
  static py::exception<InstabilityError> instability_error(m, "InstabilityError", PyExc_RuntimeError);
  static py::exception<RunFailure> run_failure(m, "RunFailure", PyExc_RuntimeError);
  static py::exception<render::RenderError> render_error(m, "RenderError", PyExc_ValueError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const CaseError& e) {
      PyErr_SetString(case_error.ptr(), e.what());
    } catch (const IoError& e) {
      PyErr_SetString(output_error.ptr(), e.what());
    } catch (const FormatError& e) {
      PyErr_SetString(format_error.ptr(), e.what());
    } catch (const InstabilityError& e) {
      PyErr_SetString(instability_error.ptr(), e.what());
    } catch (const RunFailure& e) {
      PyErr_SetString(run_failure.ptr(), e.what());
    } catch (const render::RenderError& e) {
      PyErr_SetString(render_error.ptr(), e.what());
    } catch (const std::invalid_argument& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const std::logic_error& e) {
      PyErr_SetString(PyExc_RuntimeError, e.what());
    }
  });

  py::class_<Case>(m, "Case", "A checked case: load one with sluice.load_case.")
      .def_property_readonly("name", [](const Case& c) { return c.name; })
      .def_property_readonly("dimension", [](const Case& c) { return c.dimension; })
      .def_property_readonly("dx", [](const Case& c) { return c.dx; }, "particle spacing (m)")
      .def_property_readonly("end_time", [](const Case& c) { return c.end_time; }, "time.end (s)")
      .def_property_readonly("output_interval", [](const Case& c) { return c.output_interval; })
      .def("_with_overrides", &with_overrides)
      .def("__repr__", [](const Case& c) {
        return fmt::format("<sluice.Case '{}': {}D, dx = {} m, to t = {} s>", c.name, c.dimension, c.dx, c.end_time);
      });

  m.def("_load_case", &load_case_argument);
  m.def("_parse_case", [](const std::string& text, const std::string& source) { return parse_case(text, source); });
  m.def(
      "cases",
      [] {
        std::vector<std::string> names;
        for (const BuiltinCase& b : builtin_cases()) names.push_back(b.name);
        return names;
      },
      "The names of the built-in cases.");
  m.def("simd_target", [] { return std::string(simd_target()); },
        "The instruction set the pair loop runs on, on this CPU.");

  py::class_<PySimulation>(m, "_Simulation")
      .def(py::init<const std::optional<Case>&, int, std::optional<fs::path>, std::optional<fs::path>>(), py::arg("case"),
           py::arg("threads"), py::arg("output_dir"), py::arg("restart"))
      .def("_advance", &PySimulation::advance)
      .def_property_readonly("time", [](PySimulation& s) { return s.sim().time(); }, "simulated time (s)")
      .def_property_readonly("step_count", [](PySimulation& s) { return s.sim().clock().step; },
                             "steps since t = 0")
      .def_property_readonly("dt", [](PySimulation& s) { return s.sim().clock().last_dt; }, "the last step (s)")
      .def_property_readonly("end_time", [](PySimulation& s) { return s.runner().end_time(); })
      .def_property_readonly("dimension", &PySimulation::dimension)
      .def_property_readonly("particle_count", [](PySimulation& s) { return s.sim().particle_count(); })
      .def_property_readonly("threads", [](PySimulation& s) { return s.sim().threads(); })
      .def_property_readonly("case", [](PySimulation& s) { return s.sim().config(); })
      .def_property_readonly("notes", [](PySimulation& s) { return s.sim().setup_notes(); })
      .def_property_readonly("writes_outputs", [](PySimulation& s) { return s.runner().writes_outputs(); })
      .def_property_readonly("stopped", [](PySimulation& s) { return s.runner().stopped(); })
      .def_property_readonly("closed", &PySimulation::closed)
      .def_property_readonly("_has_result", &PySimulation::has_result)
      .def("particles", &PySimulation::particles)
      .def("gather_particles", &PySimulation::gather_particles)
      .def_property_readonly("rank", [](PySimulation& s) { return s.rank(); })
      .def_property_readonly("processes", [](PySimulation& s) { return s.processes(); })
      .def_property_readonly("local_particle_count", [](PySimulation& s) {
        return s.sim().visit([](const auto& solver) { return solver.particles().size(); });
      })
      .def("_set_velocities", &PySimulation::set_velocities)
      .def("set_body_force", &PySimulation::set_body_force, py::arg("f"))
      .def("diagnostics", &PySimulation::diagnostics)
      .def("_finish", &PySimulation::finish)
      .def("_write_state_frame", [](PySimulation& s, const fs::path& dir) { write_state_frame(s, dir); })
      .def("close", &PySimulation::close);

  m.def("_render_png", &render_png, py::arg("run_dir"), py::arg("field"), py::arg("time"), py::arg("width"),
        py::arg("height"), py::arg("range"));
  m.def("_default_threads", [] { return omp_get_num_procs(); });
  m.def("_launched_by_mpi", &launched_by_mpi);
  m.def("_start_world", &start_world);

  py::exec(sluice_module_py, m.attr("__dict__"));
}
