#include "condensed_model.h"

#include <chrono>
#include <stdexcept>

#include "elastic_body.h"
#include "load_placement.h"
#include "precomputed_response.h"
#include "tool_placement.h"

namespace tb {
namespace {

class CondensedModel : public Model {
 public:
  void setup(const Problem& p) override {
    const HybridMesh& h = *p.mesh;
    if (h.fine_volume.T.rows() == 0)
      throw std::invalid_argument("condensed: the scenario provides no fine volume mesh");
    std::vector<int> outputs = h.fine_surface_to_volume;  // the fine-surface vertices are fine-volume nodes
    try {
      // Tools hold the fine-volume nodes of the surface vertices they hold, as the
      // fem model does (Dirichlet values); their responses are precomputed too.
      std::vector<PrescribedGroup> groups;
      for (const Tool& tool : p.load_case.tools) {
        if (tool.kind == ToolKind::Sphere)  // check_supported refuses it first; a direct caller gets this
          throw std::invalid_argument(tool.key + ": a sphere needs an active set, which the precomputation does not have");
        groups.push_back(fine_volume_group(tool, tool_vertices(tool, h.fine_surface, p.load_case.support),
                                           h.fine_surface_to_volume));
      }
      body_ = std::make_unique<ElasticBody>(h.fine_volume, p.material,
                                            p.load_case.support.clamp(h.fine_volume.V, "fine volume"), groups);
      loads_ = std::make_unique<BodyLoads>(
          *body_, place_on_volume(p.load_case.loads, {&h.fine_volume, "fine volume", &h.fine_surface,
                                                      &h.fine_surface_to_volume, p.material.density}));
      // Probes: the nodes of the tet holding each one are outputs too, interpolated by P1 weights.
      probes_ = place_probes(p.probes, h.fine_volume, "fine volume", false);
      for (const TetEmbedding& e : probes_)
        for (int j = 0; j < 4; ++j) outputs.push_back(h.fine_volume.T(e.tet, j));
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string("condensed: ") + e.what());
    }
    const auto t0 = std::chrono::steady_clock::now();
    response_ = std::make_unique<PrecomputedResponse>(*body_, outputs);
    if (p.parameters.choice("precompute") == "surface_vertices") response_->precompute(h.fine_surface_to_volume);
    response_->prepare(*loads_);  // the columns the scenario's loads need beyond those
    precompute_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    surface_vertices_ = static_cast<Eigen::Index>(h.fine_surface.V.rows());
    out_ = Points::Zero(static_cast<Eigen::Index>(outputs.size()), 3);
    u_ = Displacements::Zero(surface_vertices_, 3);
    probe_u_ = Points::Zero(static_cast<Eigen::Index>(probes_.size()), 3);
    reactions_.assign(p.load_case.tools.size() + 1, Eigen::Vector3d::Zero());
  }

  void step(const FrameLoads& loads) override {
    // The tools are the body's prescribed groups, in the same order (no sphere).
    response_->apply(*loads_, loads.values, loads.tool_values, out_, &reactions_);
    u_ = out_.topRows(surface_vertices_);
    for (size_t k = 0; k < probes_.size(); ++k) {
      const Eigen::Index first = surface_vertices_ + 4 * static_cast<Eigen::Index>(k);
      probe_u_.row(static_cast<Eigen::Index>(k)) = probes_[k].weights.transpose() * out_.middleRows<4>(first);
    }
  }

  const Displacements& surface_displacement() const override { return u_; }
  const std::vector<Eigen::Vector3d>* reaction_forces() const override { return &reactions_; }
  const Points* probe_displacements() const override { return &probe_u_; }

  nlohmann::json report() const override {
    return {{"loaded_nodes_precomputed", response_->nodes_computed()},
            {"response_memory_mib", response_->memory_bytes() / (1024.0 * 1024.0)},
            {"precompute_ms", precompute_ms_}};
  }

 private:
  std::unique_ptr<ElasticBody> body_;
  std::unique_ptr<BodyLoads> loads_;
  std::unique_ptr<PrecomputedResponse> response_;
  std::vector<TetEmbedding> probes_;
  Eigen::Index surface_vertices_ = 0;
  Points out_;  // every output: the surface vertices, then each probe's four tet nodes
  Displacements u_;
  Points probe_u_;
  std::vector<Eigen::Vector3d> reactions_;  // each tool's, then the support's
  double precompute_ms_ = 0;
};

}  // namespace

ModelInfo condensed_model_info() {
  ModelInfo m;
  m.name = "condensed";
  m.description =
      "Fine linear FEM condensed to the surface: precomputed responses to unit forces and unit tool translations, "
      "superposed per frame (Bro-Nielsen and Cotin 1996; Cotin et al. 1999)";
  m.parameters = {ParameterSpec::choice(
      "precompute", {"surface_vertices", "on_demand"}, "surface_vertices",
      "surface_vertices: in setup, the response to a unit force at every surface vertex (9 n^2 doubles for n "
      "surface vertices), so a point force anywhere on the surface costs no new solve; on_demand: only the nodes "
      "the scenario's loads reach. Either way a load spread over many nodes (a traction, gravity) gets the "
      "response to its own nodal forces, three solves in setup, and so does each tool")};
  m.create = [] { return std::make_unique<CondensedModel>(); };
  m.loads = {LoadKind::PointForce, LoadKind::SurfaceTraction, LoadKind::BodyForce};
  m.tools = {ToolKind::Grasp, ToolKind::BondedPlate, ToolKind::SlidingPlate};
  m.tools_how =
      "the fine-volume nodes of the held surface vertices, as Dirichlet values (the factor is of K_ff with them "
      "removed, made once for the scenario's tools); each tool's response to a unit translation of its held "
      "components (K_ff u_f = -K_fp e, three back-substitutions) precomputed and superposed each frame; a sliding "
      "plate holds the normal component only. No sphere: contact changes which dofs are held each frame, which needs "
      "the condensed surface stiffness (a Schur complement on the surface dofs) and an active set, not built";
  m.reactions = "f - K u at the held dofs, summed per tool and over the support, precomputed per column (each unit "
                "force and unit translation's reactions) and superposed: the fem model's static equilibrium, exactly";
  m.probes = "P1 interpolation in the fine tet containing the probe (its four nodes are outputs of the precomputation)";
  return m;
}

}  // namespace tb
