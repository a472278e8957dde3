#include "realtime_volume.h"

#include <stdexcept>

#include "coarse_embedded.h"

namespace tb {
namespace {

/// The coarse stepper holds the coarse nodes nearest a tool's surface vertices: it
/// has no contact set and no pads on the embedded surface.
void check_volume_takes_tools(const std::string& model_name, const Parameters& p, const LoadCase& load_case) {
  if (p.choice("volume") != "coarse_embedded") return;
  for (const Tool& tool : load_case.tools) {
    if (tool.kind == ToolKind::Sphere)
      throw std::invalid_argument(model_name + ": " + tool.key +
                                  " (sphere): volume coarse_embedded has no contact (the coarse stepper has no "
                                  "contact set on the embedded surface); use volume fine");
    if (tool.kind == ToolKind::CompliantGrasp)
      throw std::invalid_argument(model_name + ": " + tool.key +
                                  " (compliant_grasp): volume coarse_embedded has no pads (the coarse mesh is "
                                  "held at its own nodes); use volume fine");
  }
}

class OnVolume : public Model {
 public:
  OnVolume(std::string name, ElasticSolveFactory make_solve) : name_(std::move(name)), make_solve_(std::move(make_solve)) {}

  void setup(const Problem& p) override {
    volume_ = p.parameters.choice("volume");
    check_volume_takes_tools(name_, p.parameters, p.load_case);
    inner_ =
        volume_ == "coarse_embedded" ? make_coarse_embedded(name_, make_solve_) : make_fine_fem(name_, make_solve_);
    inner_->setup(p);
  }
  void step(const FrameLoads& loads) override { inner_->step(loads); }
  const Displacements& surface_displacement() const override { return inner_->surface_displacement(); }
  const std::vector<Eigen::Vector3d>* reaction_forces() const override { return inner_->reaction_forces(); }
  const std::vector<ToolContact>* tool_contacts() const override { return inner_->tool_contacts(); }
  const Points* probe_displacements() const override { return inner_->probe_displacements(); }
  int last_iterations() const override { return inner_->last_iterations(); }
  nlohmann::json report() const override {
    nlohmann::json r = inner_->report();
    r["volume"] = volume_;
    return r;
  }
  const std::vector<PhaseTime>& last_phase_times() const override { return inner_->last_phase_times(); }

 private:
  std::string name_;
  ElasticSolveFactory make_solve_;
  std::string volume_;
  std::unique_ptr<Model> inner_;
};

}  // namespace

ParameterSpec volume_parameter() {
  return ParameterSpec::choice(
      "volume", {"fine", "coarse_embedded"}, "fine",
      "the tet mesh the stepper runs on: fine (the fine tet volume, its surface nodes the fine surface) or "
      "coarse_embedded (the coarse tet volume, every fine-surface vertex moved by its barycentric weights in the "
      "nearest coarse tet, as the embedded model)");
}

std::unique_ptr<Model> make_on_volume(const std::string& model_name, ElasticSolveFactory make_solve) {
  return std::make_unique<OnVolume>(model_name, std::move(make_solve));
}

void describe_on_volume(ModelInfo& m, const std::string& fine_tools_how, const std::string& reactions,
                        const std::string& sphere_how, const std::string& pads_how) {
  describe_fine_fem(m);
  ModelInfo coarse;
  describe_coarse_fem(coarse);
  m.tools = coarse.tools;
  m.tools.push_back(ToolKind::Sphere);  // on the fine volume only (check_case refuses it on the coarse one)
  if (!pads_how.empty()) m.tools.push_back(ToolKind::CompliantGrasp);  // the same
  m.tools_how = "volume fine: the fine-volume nodes of the held surface vertices: " + fine_tools_how +
                "; a sphere: " + sphere_how + (pads_how.empty() ? "" : "; a compliant grasp: " + pads_how) +
                ". Volume coarse_embedded: the same on the coarse nodes nearest the held surface vertices (a tool "
                "smaller than the coarse spacing becomes a point-like hold); no sphere (the coarse stepper has no "
                "contact set on the embedded surface) and no compliant grasp";
  m.reactions = reactions + " (the fine or the coarse volume's nodes); a sphere: the normal part of that balance at "
                "its contact nodes (xpbd_neo: of its contact multipliers, lambda / h_sub^2)" +
                (pads_how.empty() ? "" : "; a compliant grasp: sum k_i (x_i - X_i - d) over its pads");
  m.probes = "volume fine: " + m.probes + "; volume coarse_embedded: " + coarse.probes;
  m.check_case = [model_name = m.name](const Parameters& p, const LoadCase& load_case) {
    check_volume_takes_tools(model_name, p, load_case);
  };
}

}  // namespace tb
