#include "fine_fem.h"

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <string>

#include "load_placement.h"
#include "sphere_contact.h"
#include "tool_placement.h"

namespace tb {
namespace {

class FineFem : public Model {
 public:
  FineFem(std::string name, ElasticSolveFactory make_solve) : name_(std::move(name)), make_solve_(std::move(make_solve)) {}

  void setup(const Problem& p) override {
    const HybridMesh& h = *p.mesh;
    if (h.fine_volume.T.rows() == 0) throw std::invalid_argument(name_ + ": the scenario provides no fine volume mesh");
    try {
      // Tools: the fine-volume nodes of the surface vertices they hold, as Dirichlet values.
      // Spheres hold no node: each is an active set of contacts (sphere_contact.h).
      // A compliant grasp holds them by springs (its pads) and pulls them by a load.
      std::vector<PrescribedGroup> groups;
      std::vector<NodeSpring> springs;
      for (size_t t = 0; t < p.load_case.tools.size(); ++t) {
        const Tool& tool = p.load_case.tools[t];
        const std::vector<int> held = tool_vertices(tool, h.fine_surface, p.load_case.support);
        if (tool.kind == ToolKind::Sphere) {
          spheres_.push_back(t);
          continue;
        }
        if (tool.kind == ToolKind::CompliantGrasp) {
          pads_.push_back({t, pad_springs(tool, held, h.fine_surface, h.fine_surface_to_volume)});
          springs.insert(springs.end(), pads_.back().springs.begin(), pads_.back().springs.end());
          continue;
        }
        group_of_tool_.emplace_back(t, groups.size());
        groups.push_back(fine_volume_group(tool, held, h.fine_surface_to_volume));
      }
      body_ = std::make_unique<ElasticBody>(h.fine_volume, p.material,
                                            p.load_case.support.clamp(h.fine_volume.V, "fine volume"), groups,
                                            springs);
      solve_ = make_solve_(*body_, p);
      if (!pads_.empty() && !solve_->takes_springs())
        throw std::invalid_argument(p.load_case.tools[pads_.front().tool].key +
                                    " (compliant_grasp): this solver has no springs for its pads (the linear "
                                    "solvers, newton, vbd and pd have)");
      // Eq. (10): each load's consistent nodal forces on the fine volume; then each
      // compliant grasp's pull k_i d on its pads' nodes, a load whose value is d.
      std::vector<NodalWeights> per_load = place_on_volume(
          p.load_case.loads,
          {&h.fine_volume, "fine volume", &h.fine_surface, &h.fine_surface_to_volume, p.material.density});
      for (const Pads& pads : pads_) {
        NodalWeights w;
        w.nodes.resize(static_cast<Eigen::Index>(pads.springs.size()));
        w.weights.resize(w.nodes.size());
        for (size_t i = 0; i < pads.springs.size(); ++i) {
          w.nodes(static_cast<Eigen::Index>(i)) = pads.springs[i].node;
          w.weights(static_cast<Eigen::Index>(i)) = pads.springs[i].stiffness;
        }
        per_load.push_back(std::move(w));
      }
      loads_ = std::make_unique<BodyLoads>(*body_, std::move(per_load));
      frame_ = std::make_unique<ElasticFrame>(*body_, *loads_, *solve_);
      probes_ = place_probes(p.probes, h.fine_volume, "fine volume", false);
      if (!spheres_.empty()) {
        // A nonlinear solve that takes spheres enforces them itself (the Newton solve's
        // active set, the real-time steppers'); a linear one gets the active set on K.
        if (solve_->takes_spheres())
          solve_->enable_spheres(h.fine_surface_to_volume);
        else
          contact_ = std::make_unique<SphereContact>(*body_, *solve_, h.fine_surface_to_volume);
        area_ = std::make_unique<ContactArea>(h.fine_surface);
      }
    } catch (const std::invalid_argument& e) {
      const std::string what = e.what();
      throw std::invalid_argument(what.rfind(name_ + ": ", 0) == 0 ? what : name_ + ": " + what);  // named once
    }
    load_values_.assign(p.load_case.loads.size() + pads_.size(), Eigen::Vector3d::Zero());
    reactions_.assign(p.load_case.tools.size() + 1, Eigen::Vector3d::Zero());
    contacts_.assign(p.load_case.tools.size(), ToolContact{});
    group_values_.assign(group_of_tool_.size(), Eigen::Vector3d::Zero());
    centres_ = Eigen::MatrixX3d::Zero(static_cast<Eigen::Index>(spheres_.size()), 3);
    radii_.resize(static_cast<Eigen::Index>(spheres_.size()));
    for (size_t k = 0; k < spheres_.size(); ++k) radii_(static_cast<Eigen::Index>(k)) = p.load_case.tools[spheres_[k]].radius;
    surface_to_volume_ = h.fine_surface_to_volume;
    u_ = Eigen::VectorXd::Zero(body_->dofs());
    surface_u_ = Displacements::Zero(h.fine_surface.V.rows(), 3);
  }

  void step(const FrameLoads& loads) override {
    const auto start = std::chrono::steady_clock::now();
    for (size_t g = 0; g < group_of_tool_.size(); ++g) group_values_[g] = loads.tool_values[group_of_tool_[g].first];
    std::copy(loads.values.begin(), loads.values.end(), load_values_.begin());
    for (size_t k = 0; k < pads_.size(); ++k) load_values_[loads.values.size() + k] = loads.tool_values[pads_[k].tool];
    for (size_t k = 0; k < spheres_.size(); ++k)
      centres_.row(static_cast<Eigen::Index>(k)) = loads.tool_values[spheres_[k]].transpose();
    SphereObstacles* own = solve_->spheres();
    if (own) own->set(centres_, radii_);
    frame_->step(load_values_, group_values_, u_);
    if (contact_) contact_->solve(centres_, radii_, u_);
    phases_[0].ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    // The fine surface's vertices are volume nodes: read their nodal values.
    for (size_t v = 0; v < surface_to_volume_.size(); ++v)
      surface_u_.row(static_cast<Eigen::Index>(v)) = u_.segment<3>(3 * surface_to_volume_[v]).transpose();
    if (contact_)
      measure_spheres(*contact_, nullptr);
    else if (own)
      measure_spheres(*own, solve_->internal_force());
    else {
      for (const auto& [t, g] : group_of_tool_) reactions_[t] = frame_->group_forces()[g];
      reactions_.back() = frame_->support_force();
    }
    // A compliant grasp: the force the body exerts on the jaw through its pads,
    // sum k_i (u_i - d) (the rigid grasp's f - f_int at its held nodes, in sign).
    for (const Pads& pads : pads_) {
      Eigen::Vector3d& r = reactions_[pads.tool];
      r.setZero();
      for (const NodeSpring& k : pads.springs)
        r += k.stiffness * (u_.segment<3>(3 * k.node) - loads.tool_values[pads.tool]);
    }
    interpolate_probes(probes_, body_->mesh().T, u_, probe_u_);
  }

  const std::vector<Eigen::Vector3d>* reaction_forces() const override { return &reactions_; }
  const std::vector<ToolContact>* tool_contacts() const override { return spheres_.empty() ? nullptr : &contacts_; }
  const Points* probe_displacements() const override { return &probe_u_; }

  const Displacements& surface_displacement() const override { return surface_u_; }
  int last_iterations() const override { return solve_->last_iterations(); }
  nlohmann::json report() const override {
    nlohmann::json r = {{"fine_solve", solve_->report()}};
    if (contact_) r["sphere_contact"] = contact_->report();
    return r;
  }
  const std::vector<PhaseTime>& last_phase_times() const override { return phases_; }

 private:
  /// The spheres' forces and contacts from `contact` (SphereContact or a solve's
  /// SphereObstacles: the same accessors), and the reactions of the held nodes and
  /// the support, which the contact forces moved, again at the final u (with a
  /// nonlinear solve's internal force), under this frame's load_values_.
  template <class Contact>
  void measure_spheres(const Contact& contact, const Eigen::VectorXd* internal_force) {
    loads_->assemble_full(load_values_, f_full_);
    for (const auto& [node, f] : contact.node_forces()) f_full_.segment<3>(3 * node) += f;
    body_->reactions(u_, f_full_, group_forces_, reactions_.back(), internal_force);
    for (const auto& [t, g] : group_of_tool_) reactions_[t] = group_forces_[g];
    for (size_t k = 0; k < spheres_.size(); ++k) {
      reactions_[spheres_[k]] = contact.forces()[k];
      ToolContact& c = contacts_[spheres_[k]];
      c.points = static_cast<int>(contact.contact_vertices()[k].size());
      c.area = area_->area(contact.contact_vertices()[k]);
      c.max_penetration = contact.penetration()[k];
    }
  }

  std::string name_;
  ElasticSolveFactory make_solve_;
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
  std::vector<std::pair<size_t, size_t>> group_of_tool_;  // (tool, prescribed group) of the tools that hold nodes
  struct Pads {
    size_t tool = 0;                  // a compliant grasp
    std::vector<NodeSpring> springs;  // its pads (pad_springs)
  };
  std::vector<Pads> pads_;
  std::vector<Eigen::Vector3d> load_values_;  // this frame's: the loads', then each compliant grasp's d
  std::vector<Eigen::Vector3d> group_values_, group_forces_;
  std::vector<size_t> spheres_;  // the tools that are spheres
  std::unique_ptr<SphereContact> contact_;
  std::unique_ptr<ContactArea> area_;
  Eigen::MatrixX3d centres_;
  Eigen::VectorXd radii_, f_full_;
  std::vector<ToolContact> contacts_;
};

}  // namespace

std::unique_ptr<Model> make_fine_fem(const std::string& model_name, ElasticSolveFactory make_solve) {
  return std::make_unique<FineFem>(model_name, std::move(make_solve));
}

void check_elastic_solve_takes_tools(const std::string& model_name, const Parameters& p, const std::string& prefix,
                                     const LoadCase& load_case) {
  const std::string& solver = p.choice(prefix + "solver");
  const auto refusal = [&](const ElasticSolveInfo& s, ToolKind kind) {
    if (kind == ToolKind::Sphere) return s.refuses_spheres(p, prefix);
    return kind == ToolKind::CompliantGrasp ? s.refuses_springs(p, prefix) : std::string();
  };
  for (const ElasticSolveInfo& chosen : elastic_solves()) {
    if (chosen.name != solver) continue;
    for (const Tool& tool : load_case.tools) {
      const std::string why = refusal(chosen, tool.kind);
      if (why.empty()) continue;
      std::vector<std::string> others;  // with the same parameters
      for (const ElasticSolveInfo& s : elastic_solves())
        if (refusal(s, tool.kind).empty()) others.push_back(s.name);
      std::string use;
      for (size_t i = 0; i < others.size(); ++i)
        use += (i == 0 ? "" : i + 1 == others.size() ? " or " : ", ") + others[i];
      throw std::invalid_argument(model_name + ": " + tool.key + " (" + name(tool.kind) + "): the " + solver +
                                  " solver " + why + "; use " + prefix + "solver " + use);
    }
  }
}

void describe_fine_fem(ModelInfo& m) {
  m.loads = {LoadKind::PointForce, LoadKind::SurfaceTraction, LoadKind::BodyForce};
  m.tools = {ToolKind::Grasp, ToolKind::BondedPlate, ToolKind::SlidingPlate, ToolKind::Sphere,
             ToolKind::CompliantGrasp};
  m.tools_how = "the fine-volume nodes of the held surface vertices, as Dirichlet values (K_ff u_f = f_f - K_fp u_p); "
                "a sliding plate holds the normal component only (the corotational solver: on its rotated system); a "
                "sphere: an active set of normal contact multipliers on the factorised K (direct or iterative solver), "
                "or a primal-dual active set on the linearised gaps inside Newton (newton solver, any law; not "
                "corotational); a compliant grasp: a spring k_i = pad_stiffness x vertex area from each held vertex's "
                "node to the jaw, in K (linear solvers) or in f_int and the tangent (newton; not corotational)";
  m.reactions = "f - K u at the held dofs (f - f_int(u) for the corotational and Newton solves), summed per tool "
                "and over the support (static equilibrium); a sphere: minus the sum of its contact multipliers "
                "lambda_i n_i; a compliant grasp: sum k_i (u_i - d) over its pads";
  m.probes = "P1 interpolation in the fine tet containing the probe";
}

}  // namespace tb
