#include "hybrid_model.h"

#include <stdexcept>

#include "elastic_solver.h"
#include "pbd_solver.h"

namespace tb {
namespace {

class HybridModel : public Model {
 public:
  void setup(const Problem& p) override {
    const HybridMesh& h = *p.mesh;
    if (h.coarse_volume.T.rows() == 0) throw std::invalid_argument("hybrid: the scenario provides no coarse volume");
    if (h.control_points.empty()) throw std::invalid_argument("hybrid: the hybrid mesh has no control points");
    // Step 1 (initialisation): coarse K assembled and factorised once.
    coarse_ = std::make_unique<ElasticSolver>(h.coarse_volume, p.material, p.support.select(h.coarse_volume.V),
                                              SolveMode::Direct);
    coarse_u_ = Eigen::VectorXd::Zero(3 * h.coarse_volume.V.rows());
    control_ = h.control_points;
    const SurfaceMesh& s = h.fine_surface;
    std::vector<char> fixed = p.support.select(s.V);
    pinned_.clear();
    for (const auto& cp : control_) {
      fixed[static_cast<size_t>(cp.surface_vertex)] = 1;  // never moved by the projection
      pinned_.push_back(cp.surface_vertex);
    }
    pinned_positions_ = Points::Zero(static_cast<Eigen::Index>(pinned_.size()), 3);
    apply_force_to_surface_ = p.parameters.choice("surface_force") == "nearest_vertex";
    solver_ = std::make_unique<pbd::Solver>(s, pbd::inverse_masses(s, p.material.density, fixed),
                                            pbd::Settings::from(p.parameters));
    u_ = Displacements::Zero(s.V.rows(), 3);
  }

  void step(const PointLoad& load) override {
    require_point_load(load, "hybrid");
    if (load_vertex_ < 0 || load.point != load_point_) {
      stencil_ = coarse_->locate_load(load.point);
      load_vertex_ = pbd::nearest_vertex(solver_->rest_positions(), load.point);
      load_point_ = load.point;
    }
    // Step 2: coarse K u = f (eq. 11), control points' deformed positions p'_i.
    coarse_->solve(stencil_, load.force, coarse_u_);
    const Points& rest = solver_->rest_positions();
    const auto& T = coarse_->mesh().T;
    for (size_t k = 0; k < control_.size(); ++k) {
      const ControlPoint& cp = control_[k];
      Eigen::Vector3d u = Eigen::Vector3d::Zero();
      for (int j = 0; j < 4; ++j) u += cp.weights(j) * coarse_u_.segment<3>(3 * T(cp.coarse_tet, j));
      pinned_positions_.row(static_cast<Eigen::Index>(k)) = rest.row(cp.surface_vertex) + u.transpose();
    }
    // Steps 2-5: eq. (31) on the loaded vertex, (32), (33) for control points,
    // projection of the others, (34)-(35).
    solver_->step(apply_force_to_surface_ ? load_vertex_ : -1, load.force, pinned_, pinned_positions_);
    u_ = solver_->positions() - rest;
  }

  const Displacements& surface_displacement() const override { return u_; }

 private:
  std::unique_ptr<ElasticSolver> coarse_;
  Eigen::VectorXd coarse_u_;
  std::vector<ControlPoint> control_;
  std::vector<int> pinned_;
  Points pinned_positions_;
  std::unique_ptr<pbd::Solver> solver_;
  Displacements u_;
  LoadStencil stencil_;
  int load_vertex_ = -1;
  Eigen::Vector3d load_point_;
  bool apply_force_to_surface_ = true;
};

}  // namespace

ModelInfo hybrid_model_info() {
  std::vector<ParameterSpec> specs = pbd::parameter_specs();
  specs.push_back({"surface_force",
                   0,
                   0,
                   0,
                   "nearest_vertex: eq. (31) also applies the load to the nearest free surface vertex, as in the "
                   "paper's step 2; none: the load acts only through the coarse FEM",
                   {"nearest_vertex", "none"},
                   "nearest_vertex"});
  return {"hybrid", "Coarse linear FEM pins the fine surface's control points; PBD moves the rest (paper 1.5)", true,
          specs, [] { return std::make_unique<HybridModel>(); }};
}

}  // namespace tb
