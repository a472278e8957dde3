#include "fem_distributed_model.h"

#include <mpi.h>

#include <sstream>
#include <stdexcept>

#include "distributed_elasticity.h"
#include "material_laws.h"
#include "surface_load.h"

namespace tb {
namespace {

class FemDistributedModel : public Model {
 public:
  void setup(const Problem& p) override {
    const HybridMesh& h = *p.mesh;
    if (h.fine_volume.T.rows() == 0)
      throw std::invalid_argument("fem_distributed: the scenario provides no fine volume mesh");
    surface_to_volume_ = h.fine_surface_to_volume;
    surface_u_ = Displacements::Zero(h.fine_surface.V.rows(), 3);
    p.load_case.support.clamp(h.fine_volume.V, "fine volume");  // the same support check as every model
    DistributedSettings s;
    s.degree = p.parameters.integer("degree");
    s.law = p.parameters.choice("material_law");
    s.cg_tolerance = p.parameters.number("cg_tolerance");
    s.load_steps = p.parameters.integer("load_steps");
    const SupportBox support = p.load_case.support;
    distributed_ = std::make_unique<DistributedElasticity>(
        h.fine_volume, p.material, [support](const Eigen::Vector3d& x) { return support.contains(x); }, s,
        MPI_COMM_WORLD);
    // The load's points, spread by the cells' shape functions of any degree.
    if (p.load_case.loads.size() != 1)
      throw std::invalid_argument("fem_distributed: takes exactly one load; the scenario gives " +
                                  std::to_string(p.load_case.loads.size()));
    const Load& load = p.load_case.loads[0];
    try {
      load_points_ = load.kind == LoadKind::SurfaceTraction
                         ? disc_load_points(h.fine_volume, h.fine_surface, surface_to_volume_, load.point, load.radius)
                         : point_load_points(h.fine_volume, load.point);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument("fem_distributed: " + load.key + " (" + name(load.kind) + "): " + e.what());
    }
  }

  void step(const FrameLoads& loads) override {
    distributed_->solve(load_points_, loads.values[0]);
    surface_u_ = distributed_->node_displacements(surface_to_volume_);
  }

  const Displacements& surface_displacement() const override { return surface_u_; }
  int last_iterations() const override { return distributed_->stats().cg_iterations; }

  nlohmann::json report() const override {
    const DistributedStats& s = distributed_->stats();
    return {{"dofs", s.dofs},
            {"cells", s.cells},
            {"cg_iterations_last_step", s.cg_iterations},
            {"cg_condition_estimate", s.condition_estimate},
            {"newton_iterations_last_step", s.newton_iterations},
            {"load_increments_last_step", s.load_increments},
            {"increment_halvings_last_step", s.increment_halvings},
            {"load_points", load_points_.size()},
            {"seconds",
             {{"mesh", s.mesh_s},
              {"dofs", s.dofs_s},
              {"assembly", s.assembly_s},
              {"preconditioner", s.preconditioner_s},
              {"solve_last_step", s.solve_s}}}};
  }

 private:
  std::unique_ptr<DistributedElasticity> distributed_;
  std::vector<int> surface_to_volume_;
  Displacements surface_u_;
  std::vector<LoadPoint> load_points_;  // the load's points, weights summing to 1
};

}  // namespace

ModelInfo fem_distributed_model_info() {
  using P = ParameterSpec;
  ModelInfo m;
  m.name = "fem_distributed";
  m.description =
      "FEM on the fine tet volume over MPI ranks (deal.II, Trilinos CG with ML AMG): the reference solve at any "
      "size, P1/P2, any material law of the table (linear, neo-Hookean ...), one point force or disc traction; "
      "mpirun -np N";
  std::vector<std::string> laws;
  std::string described = "the material law (numerics/materials), each with the Lame parameters of the scenario's "
                          "E and nu; every law but linear is solved by Newton with load increments. ";
  for (const MaterialLawInfo& law : material_laws()) {
    laws.push_back(law.name);
    described += law.name + ": " + law.description + "; ";
  }
  m.parameters = {
      P::whole_number("degree", 1, 1, 2, "polynomial degree of the elements, FE_SimplexP"),
      P::choice("material_law", laws, "linear", described),
      P::whole_number("load_steps", 1, 1, 1000,
                      "nonlinear laws: load increments per frame (halved when Newton fails)"),
      P::number("cg_tolerance", 1e-10, 1e-14, 1e-2, "relative residual of each linear solve (each Newton step too)")};
  m.create = [] { return std::make_unique<FemDistributedModel>(); };
  m.loads = {LoadKind::PointForce, LoadKind::SurfaceTraction};
  return m;
}

}  // namespace tb
