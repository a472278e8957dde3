#include "pbd_model.h"

#include <chrono>

#include "load_mapping.h"
#include "pbd_solver.h"

namespace tb {
namespace {

class PbdModel : public Model {
 public:
  void setup(const Problem& p) override {
    const SurfaceMesh& s = p.mesh->fine_surface;
    solver_ = std::make_unique<pbd::Solver>(
        s, pbd::inverse_masses(s, p.material.density, p.support.clamp(s.V, "fine surface")),
        pbd::Settings::from(p.parameters, p.material));
    u_ = Displacements::Zero(s.V.rows(), 3);
  }

  void step(const PointLoad& load) override {
    require_point_load(load, "pbd");
    // Eq. (31): the nearest surface vertex (DESIGN) or triangle (load_spread).
    const LoadStencil& surface_load =
        surface_load_.get(load.point, [&](const Eigen::Vector3d& x) { return solver_->locate_load(x); });
    solver_->step(surface_load, load.force, no_pins_, no_pin_positions_);
    const auto start = std::chrono::steady_clock::now();
    u_ = solver_->positions() - solver_->rest_positions();
    const double rest_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    phases_[0].ms = solver_->last_projection_ms();
    phases_[1].ms = solver_->last_integration_ms() + rest_ms;
  }

  const Displacements& surface_displacement() const override { return u_; }
  const std::vector<PhaseTime>& last_phase_times() const override { return phases_; }
  nlohmann::json report() const override { return solver_->details(); }

 private:
  std::unique_ptr<pbd::Solver> solver_;
  Displacements u_;
  PerLoadPoint<LoadStencil> surface_load_;
  std::vector<PhaseTime> phases_{{phase::kProjection}, {phase::kIntegration}};
  const std::vector<int> no_pins_;
  const Points no_pin_positions_;
};

}  // namespace

ModelInfo pbd_model_info() {
  return {"pbd", "Position Based Dynamics on the fine surface: stretch + bending constraints (paper 1.4)", true,
          pbd::parameter_specs(), [] { return std::make_unique<PbdModel>(); }};
}

}  // namespace tb
