#include "fine_fem.h"

#include <chrono>
#include <stdexcept>
#include <string>

#include "load_placement.h"
#include "tool_placement.h"

namespace tb {
namespace {

class FineFem : public Model {
 public:
  FineFem(std::string name, FineFemSolve make_solve) : name_(std::move(name)), make_solve_(std::move(make_solve)) {}

  void setup(const Problem& p) override {
    const HybridMesh& h = *p.mesh;
    if (h.fine_volume.T.rows() == 0) throw std::invalid_argument(name_ + ": the scenario provides no fine volume mesh");
    try {
      // Tools: the fine-volume nodes of the surface vertices they hold, as Dirichlet values.
      std::vector<PrescribedGroup> groups;
      for (const Tool& tool : p.load_case.tools)
        groups.push_back(fine_volume_group(tool, tool_vertices(tool, h.fine_surface, p.load_case.support),
                                           h.fine_surface_to_volume));
      body_ = std::make_unique<ElasticBody>(h.fine_volume, p.material,
                                            p.load_case.support.clamp(h.fine_volume.V, "fine volume"), groups);
      solve_ = make_solve_(*body_, p);
      // Eq. (10): each load's consistent nodal forces on the fine volume.
      loads_ = std::make_unique<BodyLoads>(
          *body_, place_on_volume(p.load_case.loads, {&h.fine_volume, "fine volume", &h.fine_surface,
                                                      &h.fine_surface_to_volume, p.material.density}));
      frame_ = std::make_unique<ElasticFrame>(*body_, *loads_, *solve_);
      probes_ = place_probes(p.probes, h.fine_volume, "fine volume", false);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(name_ + ": " + e.what());
    }
    reactions_.assign(p.load_case.tools.size() + 1, Eigen::Vector3d::Zero());
    surface_to_volume_ = h.fine_surface_to_volume;
    u_ = Eigen::VectorXd::Zero(body_->dofs());
    surface_u_ = Displacements::Zero(h.fine_surface.V.rows(), 3);
  }

  void step(const FrameLoads& loads) override {
    const auto start = std::chrono::steady_clock::now();
    frame_->step(loads.values, loads.tool_values, u_);
    phases_[0].ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    // The fine surface's vertices are volume nodes: read their nodal values.
    for (size_t v = 0; v < surface_to_volume_.size(); ++v)
      surface_u_.row(static_cast<Eigen::Index>(v)) = u_.segment<3>(3 * surface_to_volume_[v]).transpose();
    for (size_t t = 0; t + 1 < reactions_.size(); ++t) reactions_[t] = frame_->group_forces()[t];
    reactions_.back() = frame_->support_force();
    interpolate_probes(probes_, body_->mesh().T, u_, probe_u_);
  }

  const std::vector<Eigen::Vector3d>* reaction_forces() const override { return &reactions_; }
  const Points* probe_displacements() const override { return &probe_u_; }

  const Displacements& surface_displacement() const override { return surface_u_; }
  int last_iterations() const override { return solve_->last_iterations(); }
  nlohmann::json report() const override { return {{"fine_solve", solve_->report()}}; }
  const std::vector<PhaseTime>& last_phase_times() const override { return phases_; }

 private:
  std::string name_;
  FineFemSolve make_solve_;
  std::vector<PhaseTime> phases_{{phase::kSolve}};
  std::unique_ptr<ElasticBody> body_;
  std::unique_ptr<ElasticSolve> solve_;
  std::unique_ptr<BodyLoads> loads_;
  std::unique_ptr<ElasticFrame> frame_;
  std::vector<TetEmbedding> probes_;
  Points probe_u_;
  std::vector<Eigen::Vector3d> reactions_;  // each tool's, then the support's
  std::vector<int> surface_to_volume_;
  Eigen::VectorXd u_;
  Displacements surface_u_;
};

}  // namespace

std::unique_ptr<Model> make_fine_fem(const std::string& model_name, FineFemSolve make_solve) {
  return std::make_unique<FineFem>(model_name, std::move(make_solve));
}

void describe_fine_fem(ModelInfo& m) {
  m.loads = {LoadKind::PointForce, LoadKind::SurfaceTraction, LoadKind::BodyForce};
  m.tools = {ToolKind::Grasp, ToolKind::BondedPlate, ToolKind::SlidingPlate};
  m.tools_how = "the fine-volume nodes of the held surface vertices, as Dirichlet values (K_ff u_f = f_f - K_fp u_p); "
                "a sliding plate holds the normal component only (not with the corotational solver)";
  m.reactions = "f - K u at the held dofs, summed per tool and over the support (static equilibrium)";
  m.probes = "P1 interpolation in the fine tet containing the probe";
}

}  // namespace tb
