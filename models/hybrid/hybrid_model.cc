#include "hybrid_model.h"

#include <chrono>
#include <stdexcept>

#include "coarse_embedding.h"
#include "coarse_fem.h"
#include "elastic_body.h"
#include "load_placement.h"
#include "pbd_solver.h"
#include "precomputed_response.h"
#include "surface_spheres.h"
#include "tool_placement.h"

namespace tb {
namespace {

/// The ablation exact_fine_fem condenses the fine stiffness on the control points
/// under the loads alone: a tool's held vertices are not in that condensation.
void check_control_points_take_tools(const Parameters& p, const LoadCase& load_case) {
  if (p.choice("control_points") == "exact_fine_fem" && !load_case.tools.empty())
    throw std::invalid_argument("hybrid: " + load_case.tools[0].key + " (" + name(load_case.tools[0].kind) +
                                "): control_points exact_fine_fem takes no tools; use control_points coarse_fem");
}

class HybridModel : public Model {
 public:
  void setup(const Problem& p) override {
    const HybridMesh& h = *p.mesh;
    if (h.coarse_volume.T.rows() == 0) throw std::invalid_argument("hybrid: the scenario provides no coarse volume");
    if (h.control_points.empty()) throw std::invalid_argument("hybrid: the hybrid mesh has no control points");
    // Step 1 (initialisation): coarse K assembled once, and the strategy that
    // solves it each frame (parameter coarse_solver; direct: factorised here).
    // The ablation control_points = exact_fine_fem places the control points at
    // the fine FEM's solution instead (the fine stiffness condensed on them).
    check_control_points_take_tools(p.parameters, p.load_case);
    exact_control_points_ = p.parameters.choice("control_points") == "exact_fine_fem";
    try {
      if (exact_control_points_) {
        if (h.fine_volume.T.rows() == 0)
          throw std::invalid_argument("control_points exact_fine_fem needs the scenario's fine volume mesh");
        fine_body_ = std::make_unique<ElasticBody>(h.fine_volume, p.material,
                                                   p.load_case.support.clamp(h.fine_volume.V, "fine volume"));
        fine_loads_ = std::make_unique<BodyLoads>(
            *fine_body_, place_on_volume(p.load_case.loads, {&h.fine_volume, "fine volume", &h.fine_surface,
                                                             &h.fine_surface_to_volume, p.material.density}));
        std::vector<int> control_nodes;
        for (const auto& cp : h.control_points)
          control_nodes.push_back(h.fine_surface_to_volume[static_cast<size_t>(cp.surface_vertex)]);
        exact_ = std::make_unique<PrecomputedResponse>(*fine_body_, control_nodes);
        exact_->prepare(*fine_loads_);
      } else {
        // The loads on the coarse FEM: a point force by the P1 weights of the coarse
        // tet holding the point (the nearest one: the coarse hull may lie inside a
        // curved surface), or, as a study factor, all on the nearest coarse node.
        const PointInVolume rule = p.parameters.choice("coarse_load") == "nearest_node" ? PointInVolume::NearestNode
                                                                                          : PointInVolume::Nearest;
        coarse_ = std::make_unique<CoarseFem>(p, rule);
      }
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string("hybrid: coarse mesh: ") + e.what());
    }
    // Tools hold their surface vertices on the PBD surface too, pinned at rest plus
    // the tool's displacement (a sliding plate is not realised on the surface);
    // a control point a tool holds follows the tool.
    std::vector<char> held(static_cast<size_t>(h.fine_surface.V.rows()), 0);
    tool_vertices_.clear();
    for (const Tool& tool : p.load_case.tools) {
      if (tool.kind == ToolKind::SlidingPlate)
        throw std::invalid_argument("hybrid: " + tool.key + ": a sliding plate is not realised on the PBD surface");
      tool_vertices_.push_back(tool_vertices(tool, h.fine_surface, p.load_case.support));  // none for a sphere
      for (int v : tool_vertices_.back()) held[static_cast<size_t>(v)] = 1;
    }
    control_.clear();
    for (const ControlPoint& cp : h.control_points)
      if (!held[static_cast<size_t>(cp.surface_vertex)]) control_.push_back(cp);
    // surface_support coarse_fem: the surface vertices the support box holds follow
    // the coarse FEM, pinned like control points, instead of staying at rest. The
    // box clamps the coarse mesh at its own nodes only, so the coarse body can move
    // where the surface is clamped: on the liver, control points move millimetres next
    // to clamped surface vertices, a band the surface folds in (docs/liver_steady_state.md).
    supported_following_coarse_ = 0;
    if (!exact_control_points_ && p.parameters.choice("surface_support") == "coarse_fem") {
      std::vector<char> is_control(static_cast<size_t>(h.fine_surface.V.rows()));
      for (const auto& cp : control_) is_control[static_cast<size_t>(cp.surface_vertex)] = 1;
      const std::vector<char> supported = p.load_case.support.select(h.fine_surface.V);
      std::vector<int> extra;
      for (Eigen::Index v = 0; v < h.fine_surface.V.rows(); ++v)
        if (supported[static_cast<size_t>(v)] && !is_control[static_cast<size_t>(v)] && !held[static_cast<size_t>(v)])
          extra.push_back(static_cast<int>(v));
      Points at(static_cast<Eigen::Index>(extra.size()), 3);
      for (size_t k = 0; k < extra.size(); ++k) at.row(static_cast<Eigen::Index>(k)) = h.fine_surface.V.row(extra[k]);
      std::vector<ControlPoint> embedded = embed_vertices(at, h.coarse_volume);
      for (size_t k = 0; k < extra.size(); ++k) {
        embedded[k].surface_vertex = extra[k];
        control_.push_back(embedded[k]);
      }
      supported_following_coarse_ = static_cast<int>(extra.size());
    }
    control_u_ = Points::Zero(static_cast<Eigen::Index>(control_.size()), 3);
    const SurfaceMesh& s = h.fine_surface;
    std::vector<char> fixed = p.load_case.support.select(s.V);  // the control points hold the surface too
    pinned_.clear();
    for (const auto& cp : control_) {
      fixed[static_cast<size_t>(cp.surface_vertex)] = 1;  // never moved by the projection
      pinned_.push_back(cp.surface_vertex);
    }
    for (const std::vector<int>& vertices : tool_vertices_)
      for (int v : vertices) {
        fixed[static_cast<size_t>(v)] = 1;
        pinned_.push_back(v);
      }
    pinned_positions_ = Points::Zero(static_cast<Eigen::Index>(pinned_.size()), 3);
    solver_ = std::make_unique<pbd::Solver>(s, pbd::inverse_masses(s, p.material.density, fixed),
                                            pbd::Settings::from(p.parameters, p.material));
    // Eq. (31) on the surface too (the paper's step 2), unless surface_force none.
    if (p.parameters.choice("surface_force") == "applied")
      solver_->set_loads(place_on_surface(p.load_case.loads, s,
                                          solver_->settings().load_spread == pbd::LoadSpread::SurfaceTriangle,
                                          pbd::lumped_surface_masses(s, p.material.density)));
    u_ = Displacements::Zero(s.V.rows(), 3);
    // Spheres act on the PBD surface only (pbd_solver.h: a collision constraint per
    // vertex); the coarse FEM does not feel them, so a control point it pins is not moved.
    spheres_.setup(p.load_case.tools, *solver_, s);
    contacts_.assign(p.load_case.tools.size(), ToolContact{});
  }

  void step(const FrameLoads& loads) override {
    using Clock = std::chrono::steady_clock;
    using Ms = std::chrono::duration<double, std::milli>;
    // Step 2: the control points' displacement: coarse K u = f (eq. 11)
    // interpolated at their weights (eq. 33), or the fine FEM's in the ablation.
    const auto t0 = Clock::now();
    auto t1 = t0;
    if (exact_) {
      exact_->apply(*fine_loads_, loads.values, control_u_);
      t1 = Clock::now();
    } else {
      coarse_->step(loads);
      t1 = Clock::now();
      interpolate_embedded(control_, coarse_->body().mesh().T, coarse_->displacement(), control_u_);
    }
    const Points& rest = solver_->rest_positions();
    for (size_t k = 0; k < control_.size(); ++k)
      pinned_positions_.row(static_cast<Eigen::Index>(k)) =
          rest.row(control_[k].surface_vertex) + control_u_.row(static_cast<Eigen::Index>(k));
    Eigen::Index row = static_cast<Eigen::Index>(control_.size());
    for (size_t t = 0; t < tool_vertices_.size(); ++t)
      for (int v : tool_vertices_[t]) pinned_positions_.row(row++) = rest.row(v) + loads.tool_values[t].transpose();
    // Steps 2-5: eq. (31) on the loaded vertex, (32), (33) for control points,
    // projection of the others, (34)-(35).
    spheres_.move(loads, *solver_);
    const auto t2 = Clock::now();
    solver_->step(solver_->loads().empty() ? no_surface_load_values_ : loads.values, pinned_, pinned_positions_);
    const auto t3 = Clock::now();
    u_ = solver_->positions() - rest;
    if (!spheres_.empty() && coarse_) {
      reactions_ = coarse_->reactions();  // the sizes match after the first frame: no allocation
      spheres_.measure(*solver_, reactions_, contacts_);
    }
    const auto t4 = Clock::now();
    phases_[0].ms = Ms(t1 - t0).count();
    phases_[1].ms = Ms(t2 - t1).count();
    phases_[2].ms = solver_->last_projection_ms();
    phases_[3].ms = Ms(t3 - t2).count() - solver_->last_projection_ms() + Ms(t4 - t3).count();
  }

  const Displacements& surface_displacement() const override { return u_; }
  const std::vector<Eigen::Vector3d>* reaction_forces() const override {
    if (!coarse_) return nullptr;
    return spheres_.empty() ? &coarse_->reactions() : &reactions_;
  }
  const std::vector<ToolContact>* tool_contacts() const override { return spheres_.empty() ? nullptr : &contacts_; }
  const Points* probe_displacements() const override { return coarse_ ? &coarse_->probe_displacements() : nullptr; }
  /// The coarse solve's iterations (CG, corotational updates; 0 for the direct
  /// solve and the exact_fine_fem ablation), as the embedded model reports them.
  int last_iterations() const override { return coarse_ ? coarse_->last_iterations() : 0; }
  nlohmann::json report() const override {
    nlohmann::json r = solver_->details();  // the PBD sweep's threads, precision, instruction set
    if (exact_) {
      r["control_points"] = "exact_fine_fem";
      r["fine_nodes_precomputed"] = exact_->nodes_computed();
      return r;
    }
    r["control_points"] = "coarse_fem";
    if (supported_following_coarse_ > 0) r["supported_vertices_following_coarse_fem"] = supported_following_coarse_;
    coarse_->report(r);
    return r;
  }

  const std::vector<PhaseTime>& last_phase_times() const override { return phases_; }

 private:
  std::vector<PhaseTime> phases_{{phase::kCoarseSolve}, {phase::kMapping}, {phase::kProjection}, {phase::kIntegration}};
  SurfaceSpheres spheres_;
  std::vector<Eigen::Vector3d> reactions_;  // the coarse FEM's, with each sphere's PBD force
  std::vector<ToolContact> contacts_;
  bool exact_control_points_ = false;
  int supported_following_coarse_ = 0;  // surface_support coarse_fem: supported vertices pinned to the coarse FEM
  std::unique_ptr<ElasticBody> fine_body_;      // exact_fine_fem only
  std::unique_ptr<BodyLoads> fine_loads_;       // exact_fine_fem only
  std::unique_ptr<PrecomputedResponse> exact_;  // exact_fine_fem only
  Points control_u_;                            // #control points by 3
  std::unique_ptr<CoarseFem> coarse_;
  std::vector<ControlPoint> control_;
  std::vector<std::vector<int>> tool_vertices_;  // per tool: the surface vertices it pins
  std::vector<int> pinned_;
  Points pinned_positions_;
  std::unique_ptr<pbd::Solver> solver_;
  Displacements u_;
  const std::vector<Eigen::Vector3d> no_surface_load_values_;  // surface_force none: the surface gets no load
};

}  // namespace

ModelInfo hybrid_model_info() {
  std::vector<ParameterSpec> specs = pbd::parameter_specs();
  for (ParameterSpec& s : elastic_solve_parameters("coarse_", "direct", "ic")) {
    s.description = "coarse mesh: " + s.description;
    specs.push_back(std::move(s));
  }
  specs.push_back(ParameterSpec::choice(
      "control_points", {"coarse_fem", "exact_fine_fem"}, "coarse_fem",
      "coarse_fem: the paper's, control points placed by the coarse FEM (eq. 33); exact_fine_fem: an ablation "
      "beyond the paper, placed at the fine FEM's solution (the fine stiffness condensed on them), which separates "
      "the coarse mesh's error from PBD's"));
  specs.push_back(ParameterSpec::choice(
      "coarse_load", {"containing_tet", "nearest_node"}, "containing_tet",
      "how the load reaches the coarse FEM: containing_tet, spread by the P1 weights of the coarse tet holding the "
      "point (the nearest tet when it lies outside, distance in run.json); nearest_node, all on the nearest coarse "
      "node"));
  specs.push_back(ParameterSpec::choice(
      "surface_support", {"clamped", "coarse_fem"}, "clamped",
      "clamped: the surface vertices in the support box stay at rest; coarse_fem: they follow the coarse FEM, "
      "pinned as the control points are (the box clamps the coarse mesh at its own nodes only, so the coarse body "
      "can move where the surface is clamped); control_points exact_fine_fem ignores it"));
  specs.push_back(ParameterSpec::choice(
      "surface_force", {"applied", "none"}, "applied",
      "applied: eq. (31) also applies the load to the surface (where load_spread says), as in the paper's step 2; "
      "none: the load acts only through the coarse FEM"));
  ModelInfo m;
  m.name = "hybrid";
  m.description = "Coarse linear FEM pins the fine surface's control points; PBD moves the rest (paper 1.5)";
  m.dynamic = true;
  m.parameters = specs;
  m.create = [] { return std::make_unique<HybridModel>(); };
  m.loads = {LoadKind::PointForce, LoadKind::SurfaceTraction, LoadKind::BodyForce};
  describe_coarse_fem(m);
  m.tools = {ToolKind::Grasp, ToolKind::BondedPlate, ToolKind::Sphere};
  m.check_case = check_control_points_take_tools;
  m.tools_how = "a sphere: a collision constraint on the PBD surface only, as in pbd (the coarse FEM does not feel "
                "it; control points are not moved by it). Other tools: the coarse FEM holds the coarse nodes nearest the tool's surface vertices (Dirichlet values); PBD "
                "pins the surface vertices themselves at rest plus the tool's displacement (eq. 33), a control point "
                "among them following the tool. Not with control_points exact_fine_fem; no sliding plate";
  m.reactions = "the coarse FEM's f - K u at the held coarse dofs (the elastic part of the hybrid; PBD's surface "
                "carries no force units); a sphere: its PBD collision force, as in pbd";
  return m;
}

}  // namespace tb
