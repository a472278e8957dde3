// tissuebench.Run: one case of a scenario set up and stepped from Python, by the
// code the runner steps it with (experiments/case_run.h, CaseRun): the same
// meshes (through the same cache), the same checks before setup, the same frame
// and the same one-line errors. Nothing is written to disk; the results are numpy
// arrays. The GIL is released while C++ builds the meshes, sets the model up and
// steps it, so other Python threads run meanwhile.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "case_run.h"
#include "mesh_recipe.h"
#include "python_bindings.h"
#include "runner.h"

namespace tb::python {
namespace {

/// The index of the case called `name` in `s`; throws naming the file and the cases it has.
size_t case_index(const Scenario& s, const std::string& name) {
  std::string known;
  for (size_t k = 0; k < s.models.size(); ++k) {
    if (s.models[k].case_name == name) return k;
    known += (k ? ", " : "") + s.models[k].case_name;
  }
  throw std::invalid_argument(s.file + ": scenario '" + s.name + "' has no case '" + name + "' (its cases: " + known +
                              ")");
}

class Run {
 public:
  /// Builds the scenario's meshes (read from `mesh_cache` when built before; None:
  /// the program's default cache, "": no cache), places its tools and probes and
  /// sets the case's model up.
  Run(std::shared_ptr<Scenario> scenario, const std::string& case_name, const std::optional<std::string>& mesh_cache)
      : given_(std::move(scenario)), index_(case_index(*given_, case_name)), label_(given_->name + "/" + case_name) {
    const std::string cache = mesh_cache.value_or(default_mesh_cache_dir());
    try {
      py::gil_scoped_release release;
      MeshReport report;
      bool from_cache = false;
      mesh_ = std::make_shared<HybridMesh>(build_mesh_cached(given_->mesh, report, cache, from_cache));
      placed_ = placed_on_mesh(*given_, mesh_->fine_surface);
      case_ = std::make_unique<CaseRun>(placed_, placed_.models[index_], *mesh_);
      case_->setup();
    } catch (const std::exception& e) {
      throw std::runtime_error(label_ + " failed: " + e.what());  // the tissuebench program's line
    }
    after_step();
  }

  void step() {
    check_can_step();
    busy_ = true;  // read and written with the GIL held: one step at a time per Run
    try {
      py::gil_scoped_release release;
      case_->step();
    } catch (const std::exception& e) {
      busy_ = false;
      error_ = e.what();
      after_step();
      throw std::runtime_error(label_ + " failed: " + error_);
    }
    busy_ = false;
    step_ms_.push_back(case_->last_step_ms());
    after_step();
  }

  int run() {
    if (!error_.empty() || busy_) check_can_step();
    while (!state_.finished) {
      step();
      if (PyErr_CheckSignals() != 0) throw py::error_already_set();  // Ctrl-C between frames
    }
    return state_.frames;
  }

  /// Where the case is, as of the last frame; readable while another thread steps.
  struct State {
    int frames = 0, budget = 0, steady_frame = -1;
    bool finished = false, dynamic = false;
    double setup_ms = 0;
  };
  const State& state() const { return state_; }
  /// The case and its model, between steps only: while another thread steps (the
  /// GIL released), reading the model's arrays would race with the frame writing them.
  const CaseRun& case_run() const {
    if (busy_) throw std::runtime_error(label_ + ": stepping in another thread; read its results between steps");
    return *case_;
  }
  const Scenario& scenario() const { return placed_; }
  const ModelRun& model_run() const { return placed_.models[index_]; }
  const HybridMesh& mesh() const { return *mesh_; }
  const std::vector<double>& step_ms() const { return step_ms_; }
  const std::string& error() const { return error_; }

 private:
  void after_step() {
    state_ = {case_->frames(),   case_->budget(),       case_->steady_frame(),
              case_->finished(), case_->info().dynamic, case_->setup_ms()};
  }

  void check_can_step() const {
    if (busy_) throw std::runtime_error(label_ + ": already stepping in another thread");
    if (!error_.empty())
      throw std::runtime_error(label_ + " failed at frame " + std::to_string(state_.frames - 1) +
                               ", before this step: " + error_ + " (make a new Run to start again)");
    if (state_.finished) {
      const int steady = state_.steady_frame;
      throw std::runtime_error(label_ + ": no frame left after " + std::to_string(state_.frames) + " frames (" +
                               (steady >= 0 ? "steady from frame " + std::to_string(steady)
                                            : "the frame budget of " + std::to_string(state_.budget) + " frames") +
                               ")");
    }
  }

  std::shared_ptr<const Scenario> given_;  // keeps its Experiment alive
  size_t index_;
  std::string label_;  // scenario/case, as the program names a case
  std::shared_ptr<HybridMesh> mesh_;
  Scenario placed_;  // given_ placed on mesh_
  std::unique_ptr<CaseRun> case_;
  std::vector<double> step_ms_;
  std::string error_;  // why a step failed; then no step more
  State state_;        // written with the GIL held, after each step
  bool busy_ = false;
};

/// #rows by 3, from a list of vectors.
Points rows_of(const std::vector<Eigen::Vector3d>& v) {
  Points out(static_cast<Eigen::Index>(v.size()), 3);
  for (size_t k = 0; k < v.size(); ++k) out.row(static_cast<Eigen::Index>(k)) = v[k].transpose();
  return out;
}

}  // namespace

void bind_run(py::module_& m) {
  py::class_<Run>(m, "Run", R"(One case of a scenario, set up and stepped from Python as `tissuebench run` steps it
(experiments/case_run.h): the same meshes, checks, frames and errors; nothing written.

    run = tissuebench.Run(scenario, "fem-direct")   # meshes built (or read from the cache), model set up
    run.step()                                     # one frame
    run.run()                                      # the remaining frames, to the budget or the steady state
    run.displacement                               # #V by 3 numpy array, m

A frame that fails (a diverged surface, a tunnelled sphere) raises tissuebench.Error
with the program's line ("<scenario>/<case> failed: ..."); every later step raises it
again. The GIL is released while C++ builds, sets up and steps.)")
      .def(py::init<std::shared_ptr<Scenario>, const std::string&, const std::optional<std::string>&>(),
           py::arg("scenario"), py::arg("case"), py::arg("mesh_cache") = py::none(),
           "scenario: a tissuebench.Scenario; case: one of its case names; mesh_cache: the folder of built meshes "
           "(None: the program's default, $TISSUEBENCH_MESH_CACHE or ~/.cache/tissuebench/meshes; '': none)")
      .def("step", &Run::step, "Steps one frame. tissuebench.Error when it fails, or no frame is left.")
      .def("run", &Run::run, "Steps until the frame budget is spent or a dynamic model is steady; returns the frames.")
      .def_property_readonly("scenario", [](const Run& r) { return r.scenario().name; })
      .def_property_readonly("case", [](const Run& r) { return r.model_run().case_name; })
      .def_property_readonly("model", [](const Run& r) { return r.model_run().model; })
      .def_property_readonly("dynamic", [](const Run& r) { return r.state().dynamic; })
      .def_property_readonly(
          "frames", [](const Run& r) { return r.state().frames; }, "frames stepped")
      .def_property_readonly(
          "budget", [](const Run& r) { return r.state().budget; },
          "frames at most: frames.max for a dynamic model, frames.static (at least the ramp's) for a static one")
      .def_property_readonly(
          "finished", [](const Run& r) { return r.state().finished; },
          "the budget is spent or a dynamic model is steady")
      .def_property_readonly(
          "steady_frame", [](const Run& r) { return r.state().steady_frame; },
          "a dynamic model's first steady frame; -1 before it and for a static model")
      .def_property_readonly(
          "error",
          [](const Run& r) -> py::object {
            if (r.error().empty()) return py::none();
            return py::str(r.error());
          },
          "why a step failed, or None")
      .def_property_readonly(
          "setup_ms", [](const Run& r) { return r.state().setup_ms; }, "the model's setup, ms")
      .def_property_readonly(
          "step_ms",
          [](const Run& r) {
            return py::array_t<double>(static_cast<py::ssize_t>(r.step_ms().size()), r.step_ms().data());
          },
          "each frame's step, ms (the runner's timed region: timings.json step_ms_per_frame)")
      .def_property_readonly(
          "last_iterations", [](const Run& r) { return r.case_run().model().last_iterations(); },
          "the solver's iterations in the last frame, where meaningful (else 0)")
      .def_property_readonly(
          "rest_positions", [](const Run& r) { return Points(r.mesh().fine_surface.V); },
          "#V by 3 rest positions of the fine-surface vertices, m")
      .def_property_readonly(
          "faces", [](const Run& r) { return Triangles(r.mesh().fine_surface.F); },
          "#F by 3 vertex indices of the fine surface's triangles, outward")
      .def_property_readonly(
          "displacement",
          [](const Run& r) {
            if (r.state().frames == 0) return Points(Points::Zero(r.mesh().fine_surface.V.rows(), 3));
            return Points(r.case_run().model().surface_displacement());
          },
          "#V by 3 displacements of the fine-surface vertices after the last frame, m (zeros before the first); "
          "the rows of surface.csv")
      .def_property_readonly(
          "probe_points", [](const Run& r) { return Points(r.scenario().probes); },
          "#P by 3 interior points the scenario observes (\"probes\"), m")
      .def_property_readonly(
          "probes",
          [](const Run& r) -> py::object {
            const Points* p = r.state().frames > 0 ? r.case_run().model().probe_displacements() : nullptr;
            if (!p || r.scenario().probes.rows() == 0) return py::none();
            return py::cast(Points(*p));
          },
          "#P by 3 displacements at probe_points after the last frame, m; None before the first frame, without "
          "probes or for a model with no volume")
      .def_property_readonly(
          "reaction_names",
          [](const Run& r) {
            std::vector<std::string> out;
            for (const ScenarioTool& t : r.scenario().tools) out.push_back(t.tool.key);
            out.push_back("support");
            return out;
          },
          "what each row of reactions is: each tool's key (LoadCase order), then 'support'")
      .def_property_readonly(
          "reactions",
          [](const Run& r) -> py::object {
            const auto* f = r.state().frames > 0 ? r.case_run().model().reaction_forces() : nullptr;
            if (!f) return py::none();
            return py::cast(rows_of(*f));
          },
          "(#tools + 1) by 3 forces the tissue exerts on each tool and the support after the last frame, N; None "
          "before the first frame or for a model that does not measure them")
      .def(
          "report", [](const Run& r) { return to_python(r.case_run().model().report()); },
          "what the model reports of its setup (run.json model_report), a dict")
      .def("__repr__", [](const Run& r) {
        return "<tissuebench.Run " + r.scenario().name + "/" + r.model_run().case_name + ", frame " +
               std::to_string(r.state().frames) + " of " + std::to_string(r.state().budget) + ">";
      });
}

}  // namespace tb::python
