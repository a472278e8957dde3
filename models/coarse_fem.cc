#include "coarse_fem.h"

#include "tool_placement.h"

namespace tb {

CoarseFem::CoarseFem(const Problem& p, PointInVolume point_rule, const ElasticSolveFactory& make_solve) {
  const HybridMesh& h = *p.mesh;
  const std::vector<char> clamped = p.load_case.support.clamp(h.coarse_volume.V, "coarse volume");
  std::vector<PrescribedGroup> groups;
  // A sphere holds no node (the hybrid realises it on the PBD surface only).
  for (size_t t = 0; t < p.load_case.tools.size(); ++t) {
    const Tool& tool = p.load_case.tools[t];
    const std::vector<int> held = tool_vertices(tool, h.fine_surface, p.load_case.support);
    if (tool.kind == ToolKind::Sphere) continue;
    group_of_tool_.emplace_back(t, groups.size());
    groups.push_back(coarse_volume_group(tool, held, h.fine_surface.V, h.coarse_volume, clamped));
  }
  group_values_.assign(groups.size(), Eigen::Vector3d::Zero());
  body_ = std::make_unique<ElasticBody>(h.coarse_volume, p.material, clamped, groups);
  solve_ = make_solve ? make_solve(*body_, p) : make_elastic_solve(*body_, p.parameters, "coarse_");
  loads_ = std::make_unique<BodyLoads>(
      *body_, place_on_volume(p.load_case.loads, {&h.coarse_volume, "coarse volume", &h.fine_surface, nullptr,
                                                  p.material.density, point_rule}));
  frame_ = std::make_unique<ElasticFrame>(*body_, *loads_, *solve_);
  probes_ = place_probes(p.probes, h.coarse_volume, "coarse volume", true);
  u_ = Eigen::VectorXd::Zero(body_->dofs());
  reactions_.assign(p.load_case.tools.size() + 1, Eigen::Vector3d::Zero());
}

void CoarseFem::step(const FrameLoads& loads) {
  for (const auto& [t, g] : group_of_tool_) group_values_[g] = loads.tool_values[t];
  frame_->step(loads.values, group_values_, u_);
  for (const auto& [t, g] : group_of_tool_) reactions_[t] = frame_->group_forces()[g];
  reactions_.back() = frame_->support_force();
  interpolate_probes(probes_, body_->mesh().T, u_, probe_u_);
}

void CoarseFem::report(nlohmann::json& r) const {
  r["coarse_solve"] = solve_->report();
  if (loads_->size() > 0) r["load_distance_to_coarse_mesh_m"] = loads_->load(0).distance;
}

void describe_coarse_fem(ModelInfo& info) {
  info.tools = {ToolKind::Grasp, ToolKind::BondedPlate, ToolKind::SlidingPlate};
  info.tools_how =
      "the coarse nodes nearest the held surface vertices, as Dirichlet values of the coarse FEM (a tool smaller "
      "than the coarse spacing becomes a point-like hold); a sliding plate holds the normal component only";
  info.reactions = "the coarse FEM's f - K u at the held coarse dofs, per tool and over the support";
  info.probes = "P1 interpolation in the nearest coarse tet (extrapolated outside the coarse hull)";
}

}  // namespace tb
