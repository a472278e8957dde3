#include "pbd_model.h"

#include "pbd_solver.h"

namespace tb {
namespace {

class PbdModel : public Model {
 public:
  void setup(const Problem& p) override {
    const SurfaceMesh& s = p.mesh->fine_surface;
    solver_ = std::make_unique<pbd::Solver>(s, pbd::inverse_masses(s, p.material.density, p.support.select(s.V)),
                                            pbd::Settings::from(p.parameters));
    u_ = Displacements::Zero(s.V.rows(), 3);
  }

  void step(const PointLoad& load) override {
    require_point_load(load, "pbd");
    if (load_vertex_ < 0 || load.point != load_point_) {
      load_vertex_ = pbd::nearest_vertex(solver_->rest_positions(), load.point);  // DESIGN: nearest surface vertex
      load_point_ = load.point;
    }
    solver_->step(load_vertex_, load.force, no_pins_, no_pin_positions_);
    u_ = solver_->positions() - solver_->rest_positions();
  }

  const Displacements& surface_displacement() const override { return u_; }

 private:
  std::unique_ptr<pbd::Solver> solver_;
  Displacements u_;
  int load_vertex_ = -1;
  Eigen::Vector3d load_point_;
  const std::vector<int> no_pins_;
  const Points no_pin_positions_;
};

}  // namespace

ModelInfo pbd_model_info() {
  return {"pbd", "Position Based Dynamics on the fine surface: stretch + bending constraints (paper 1.4)", true,
          pbd::parameter_specs(), [] { return std::make_unique<PbdModel>(); }};
}

}  // namespace tb
