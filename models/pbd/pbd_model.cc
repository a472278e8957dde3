#include "pbd_model.h"

#include <chrono>

#include "load_placement.h"
#include "pbd_solver.h"
#include "surface_spheres.h"
#include "tool_placement.h"

namespace tb {
namespace {

class PbdModel : public Model {
 public:
  void setup(const Problem& p) override {
    const SurfaceMesh& s = p.mesh->fine_surface;
    // Tools pin the surface vertices they hold (inverse mass 0) at rest plus their
    // displacement each frame (eq. 33, as the hybrid's control points).
    std::vector<char> fixed = p.load_case.support.clamp(s.V, "fine surface");
    // Reaction groups: each tool's pinned vertices, then the support's (the last).
    const int n_tools = static_cast<int>(p.load_case.tools.size());
    std::vector<int> group(fixed.size(), -1);
    for (size_t v = 0; v < fixed.size(); ++v)
      if (fixed[v]) group[v] = n_tools;
    for (size_t t = 0; t < p.load_case.tools.size(); ++t) {
      const Tool& tool = p.load_case.tools[t];
      tool_vertices_.push_back(tool_vertices(tool, s, p.load_case.support));  // none for a sphere
      for (int v : tool_vertices_.back()) {
        fixed[static_cast<size_t>(v)] = 1;
        group[static_cast<size_t>(v)] = static_cast<int>(t);
        pinned_.push_back(v);
      }
    }
    pinned_positions_ = Points::Zero(static_cast<Eigen::Index>(pinned_.size()), 3);
    solver_ = std::make_unique<pbd::Solver>(s, pbd::inverse_masses(s, p.material.density, fixed),
                                            pbd::Settings::from(p.parameters, p.material));
    // Eq. (31): a point force on the nearest surface vertex (the paper) or triangle
    // (load_spread); a traction on its disc's triangles; gravity on every vertex's mass.
    solver_->set_loads(place_on_surface(p.load_case.loads, s,
                                        solver_->settings().load_spread == pbd::LoadSpread::SurfaceTriangle,
                                        pbd::lumped_surface_masses(s, p.material.density)));
    solver_->set_reaction_groups(group, n_tools + 1);
    u_ = Displacements::Zero(s.V.rows(), 3);
    // Spheres: a collision constraint per surface vertex near each (pbd_solver.h).
    spheres_.setup(p.load_case.tools, *solver_, s);
    reactions_.assign(p.load_case.tools.size() + 1, Eigen::Vector3d::Zero());
    contacts_.assign(p.load_case.tools.size(), ToolContact{});
  }

  void step(const FrameLoads& loads) override {
    Eigen::Index row = 0;
    for (size_t t = 0; t < tool_vertices_.size(); ++t)
      for (int v : tool_vertices_[t])
        pinned_positions_.row(row++) = solver_->rest_positions().row(v) + loads.tool_values[t].transpose();
    spheres_.move(loads, *solver_);
    solver_->step(loads.values, pinned_, pinned_positions_);
    reactions_ = solver_->group_forces();  // each tool's pins (zero for a sphere), then the support's
    spheres_.measure(*solver_, reactions_, contacts_);
    const auto start = std::chrono::steady_clock::now();
    u_ = solver_->positions() - solver_->rest_positions();
    const double rest_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    phases_[0].ms = solver_->last_projection_ms();
    phases_[1].ms = solver_->last_integration_ms() + rest_ms;
  }

  const Displacements& surface_displacement() const override { return u_; }
  const std::vector<Eigen::Vector3d>* reaction_forces() const override { return &reactions_; }
  const std::vector<ToolContact>* tool_contacts() const override { return spheres_.empty() ? nullptr : &contacts_; }
  const std::vector<PhaseTime>& last_phase_times() const override { return phases_; }
  nlohmann::json report() const override { return solver_->details(); }

 private:
  std::unique_ptr<pbd::Solver> solver_;
  Displacements u_;
  std::vector<PhaseTime> phases_{{phase::kProjection}, {phase::kIntegration}};
  std::vector<std::vector<int>> tool_vertices_;  // per tool: the surface vertices it pins
  std::vector<int> pinned_;                      // every tool's, in tool order
  Points pinned_positions_;
  SurfaceSpheres spheres_;
  std::vector<Eigen::Vector3d> reactions_;  // each tool's force, then the support's
  std::vector<ToolContact> contacts_;
};

}  // namespace

ModelInfo pbd_model_info() {
  ModelInfo m;
  m.name = "pbd";
  m.description = "Position Based Dynamics on the fine surface: stretch + bending constraints (paper 1.4)";
  m.dynamic = true;
  m.parameters = pbd::parameter_specs();
  m.create = [] { return std::make_unique<PbdModel>(); };
  m.loads = {LoadKind::PointForce, LoadKind::SurfaceTraction, LoadKind::BodyForce};
  m.tools = {ToolKind::Grasp, ToolKind::BondedPlate, ToolKind::Sphere};
  m.tools_how = "the held surface vertices pinned (inverse mass 0) at rest plus the tool's displacement, eq. (33); "
                "no sliding plate (a pin holds all three components); a sphere: each surface vertex inside it "
                "projected to its surface after every sweep (collision constraint, Mueller et al. 2007)";
  m.reactions = "a grasp, a plate, the support: -sum over the constraints joining its pinned vertices to free ones of "
                "the momentum they gave the free vertices (sum m_j dp_j over the step's sweeps) / h^2 per sub-step h, "
                "averaged over the sub-steps, plus the loads' shares on its own vertices (at rest: (1 - damping) of the "
                "load on the free vertices, PBD's damping taking the rest); a sphere: -sum over the vertices it moved "
                "of mass x collision correction / h^2, averaged alike";
  return m;
}

}  // namespace tb
