#include "case_run.h"

#include <algorithm>
#include <chrono>
#include <sstream>
#include <stdexcept>
#include <string>

#include "mesh_checks.h"

namespace tb {
using Clock = std::chrono::steady_clock;

Scenario placed_on_mesh(const Scenario& scenario, const SurfaceMesh& surface) {
  Scenario placed = scenario;
  resolve_on_mesh(placed, surface);
  check_on_mesh(placed, surface);
  return placed;
}

namespace {

/// The frames a case runs at most (CaseRun::budget).
int frame_budget(const Scenario& s, const ModelRun& run, const ModelInfo& info) {
  if (info.dynamic) return run.max_frames > 0 ? std::min(run.max_frames, s.max_frames) : s.max_frames;
  return std::max(s.static_frames, s.changing_frames());
}

/// The model, once its loads and tools are known to be ones it takes.
std::unique_ptr<Model> checked_model(const ModelInfo& info, const Problem& problem) {
  check_supported(info, problem.parameters, problem.load_case);
  return info.create();
}

}  // namespace

CaseRun::CaseRun(const Scenario& scenario, const ModelRun& run, const HybridMesh& mesh)
    : scenario_(scenario),
      info_(find_model(run.model)),
      problem_{&mesh, scenario.material, scenario.load_case(), run.parameters, scenario.probes},
      model_(checked_model(info_, problem_)),
      sphere_guard_(problem_.load_case.tools, mesh.fine_surface),
      changing_(scenario.changing_frames()),
      budget_(frame_budget(scenario, run, info_)),
      divergence_bound_(scenario.divergence_factor * bounding_box_diagonal(mesh.fine_surface.V)),
      previous_(Displacements::Zero(mesh.fine_surface.V.rows(), 3)) {}

void CaseRun::setup() {
  if (set_up_) throw std::logic_error("CaseRun::setup called twice");
  const auto t0 = Clock::now();
  model_->setup(problem_);
  setup_ms_ = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  set_up_ = true;
}

void CaseRun::step() {
  if (!set_up_) throw std::logic_error("CaseRun::step before setup");
  if (finished()) throw std::logic_error("CaseRun::step after the last frame");
  const int frame = frames_;
  scenario_.loads_at(frame, loads_);
  const auto a = Clock::now();
  model_->step(loads_);
  last_step_ms_ = std::chrono::duration<double, std::milli>(Clock::now() - a).count();
  frames_ = frame + 1;

  const Displacements& u = model_->surface_displacement();
  if (!u.allFinite())
    throw std::runtime_error("diverged at frame " + std::to_string(frame) + ": NaN or Inf displacement");
  const double max_u = u.rowwise().norm().maxCoeff();
  if (max_u > divergence_bound_) {
    std::ostringstream msg;
    if (info_.dynamic)
      msg << "diverged at frame " << frame << ": displacement " << max_u << " m exceeds " << divergence_bound_
          << " m (divergence_factor x bounding-box diagonal)";
    else  // a static solve cannot diverge: the load is too large for the material
      msg << "the static solution at frame " << frame << " displaces a vertex by " << max_u << " m, beyond "
          << divergence_bound_ << " m (divergence_factor x bounding-box diagonal): a linear small-strain solution "
          << "far outside its range (reduce the load or stiffen the material)";
    throw std::runtime_error(msg.str());
  }
  if (sphere_guard_.active()) {
    const auto g = Clock::now();
    sphere_guard_.check(frame, u, loads_.tool_values);
    last_sphere_guard_ms_ = std::chrono::duration<double, std::milli>(Clock::now() - g).count();
  }
  last_change_ = (u - previous_).rowwise().norm().maxCoeff();
  previous_ = u;
  if (info_.dynamic && frame + 1 >= changing_ && last_change_ <= scenario_.steady_tolerance * max_u)
    steady_frame_ = frame;
}

}  // namespace tb
