#include "fem_distributed_model.h"

#include <mpi.h>

#include <sstream>
#include <stdexcept>

#include "distributed_elasticity.h"
#include "material_laws.h"
#include "surface_load.h"
#include "tool_placement.h"

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
    DistributedSettings s;
    s.degree = p.parameters.integer("degree");
    s.law = p.parameters.choice("material_law");
    s.cg_tolerance = p.parameters.number("cg_tolerance");
    s.load_steps = p.parameters.integer("load_steps");
    // Tools: the fine-volume nodes of the surface vertices they hold (the same
    // translation as every model, tool_placement.h), held as inhomogeneous
    // Dirichlet constraints; probes: their tets in the fine volume.
    std::vector<PrescribedGroup> groups;
    std::vector<TetEmbedding> probes;
    try {
      p.load_case.support.clamp(h.fine_volume.V, "fine volume");  // the same support check as every model
      for (const Tool& tool : p.load_case.tools)
        groups.push_back(fine_volume_group(tool, tool_vertices(tool, h.fine_surface, p.load_case.support),
                                           h.fine_surface_to_volume));
      probes = place_probes(p.probes, h.fine_volume, "fine volume", false);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string("fem_distributed: ") + e.what());
    }
    const SupportBox support = p.load_case.support;
    distributed_ = std::make_unique<DistributedElasticity>(
        h.fine_volume, p.material, [support](const Eigen::Vector3d& x) { return support.contains(x); }, s,
        MPI_COMM_WORLD, DistributedElasticity::Field(), groups);
    std::vector<int> tets;
    for (const TetEmbedding& e : probes) tets.push_back(e.tet);
    distributed_->set_probes(p.probes, tets);
    // Body forces: their accelerations add up each frame (the engine integrates
    // rho g over the cells); the one point force or traction: its points, spread
    // by the cells' shape functions of any degree.
    point_load_ = -1;
    body_loads_.clear();
    for (size_t k = 0; k < p.load_case.loads.size(); ++k) {
      const Load& load = p.load_case.loads[k];
      const std::string where = "fem_distributed: " + load.key + " (" + name(load.kind) + "): ";
      if (load.kind == LoadKind::BodyForce) {
        if (!(p.material.density > 0)) throw std::invalid_argument(where + "a body force needs a positive density");
        body_loads_.push_back(k);
        continue;
      }
      if (point_load_ >= 0)
        throw std::invalid_argument(where + "takes at most one point force or surface traction; " +
                                    p.load_case.loads[static_cast<size_t>(point_load_)].key + " is one");
      point_load_ = static_cast<int>(k);
      try {
        load_points_ =
            load.kind == LoadKind::SurfaceTraction
                ? disc_load_points(h.fine_volume, h.fine_surface, surface_to_volume_, load.point, load.radius)
                : point_load_points(h.fine_volume, load.point);
      } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(where + e.what());
      }
    }
  }

  void step(const FrameLoads& loads) override {
    Eigen::Vector3d gravity = Eigen::Vector3d::Zero();
    for (size_t k : body_loads_) gravity += loads.values[k];
    distributed_->solve(load_points_,
                        point_load_ < 0 ? Eigen::Vector3d::Zero() : loads.values[static_cast<size_t>(point_load_)],
                        loads.tool_values, gravity);
    surface_u_ = distributed_->node_displacements(surface_to_volume_);
    reactions_ = distributed_->reactions();
    probe_u_ = distributed_->probe_displacements();
  }

  const std::vector<Eigen::Vector3d>* reaction_forces() const override { return &reactions_; }
  const Points* probe_displacements() const override { return &probe_u_; }
  const Displacements& surface_displacement() const override { return surface_u_; }
  int last_iterations() const override { return distributed_->stats().cg_iterations; }

  nlohmann::json report() const override {
    const DistributedStats& s = distributed_->stats();
    return {{"dofs", s.dofs},
            {"cells", s.cells},
            {"cg_iterations_last_step", s.cg_iterations},
            {"cg_condition_estimate", s.condition_estimate},
            {"supported_dofs", s.supported_dofs},
            {"held_dofs", s.held_dofs},
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
  std::vector<LoadPoint> load_points_;      // the point load's or traction's points, weights summing to 1
  int point_load_ = -1;                     // its index in the load case, or -1: none
  std::vector<size_t> body_loads_;          // the body forces' indices in the load case
  std::vector<Eigen::Vector3d> reactions_;  // each tool's, then the support's
  Points probe_u_;
};

}  // namespace

ModelInfo fem_distributed_model_info() {
  using P = ParameterSpec;
  ModelInfo m;
  m.name = "fem_distributed";
  m.description =
      "FEM on the fine tet volume over MPI ranks (deal.II, Trilinos CG with ML AMG): the reference solve at any "
      "size, P1/P2, any material law of the table (linear, neo-Hookean ...), one point force or disc traction, "
      "gravity (int rho g N_i over the reference cells, a dead load), grasps and plates; mpirun -np N";
  std::vector<std::string> laws;
  std::string described =
      "the material law (numerics/materials), each with the Lame parameters of the scenario's "
      "E and nu; every law but linear is solved by Newton with load increments. ";
  for (const MaterialLawInfo& law : material_laws()) {
    laws.push_back(law.name);
    described += law.name + ": " + law.description + "; ";
  }
  m.parameters = {
      P::whole_number("degree", 1, 1, 2, "polynomial degree of the elements, FE_SimplexP"),
      P::choice("material_law", laws, "linear", described),
      P::whole_number("load_steps", 1, 1, 1000, "nonlinear laws: load increments per frame (halved when Newton fails)"),
      P::number("cg_tolerance", 1e-10, 1e-14, 1e-2, "relative residual of each linear solve (each Newton step too)")};
  m.create = [] { return std::make_unique<FemDistributedModel>(); };
  m.spans_ranks = true;
  m.loads = {LoadKind::PointForce, LoadKind::SurfaceTraction, LoadKind::BodyForce};
  m.tools = {ToolKind::Grasp, ToolKind::BondedPlate, ToolKind::SlidingPlate};
  m.tools_how =
      "the fine-volume nodes of the held surface vertices and (P2) the midside dofs of the boundary edges both of "
      "whose nodes are held, as inhomogeneous Dirichlet constraints (deal.II AffineConstraints); a sliding plate "
      "holds the normal component only; nonlinear laws: each load increment's first Newton step moves the held dofs "
      "by their increment, the later steps keep them";
  m.reactions =
      "the loads' share (gravity's included) minus the internal force (K u, or the law's f_int(u)) at the held "
      "dofs, summed per tool and over the support";
  m.probes = "the P1 or P2 field of the fine tet containing the probe, at its reference point (the owning rank's)";
  return m;
}

}  // namespace tb
