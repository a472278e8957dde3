#include "surface_spheres.h"

namespace tb {

void SurfaceSpheres::setup(const std::vector<Tool>& tools, pbd::Solver& solver, const SurfaceMesh& surface) {
  tools_.clear();
  for (size_t t = 0; t < tools.size(); ++t)
    if (tools[t].kind == ToolKind::Sphere) tools_.push_back(t);
  centres_ = Points::Zero(static_cast<Eigen::Index>(tools_.size()), 3);
  radii_.resize(static_cast<Eigen::Index>(tools_.size()));
  for (size_t k = 0; k < tools_.size(); ++k) {
    centres_.row(static_cast<Eigen::Index>(k)) = tools[tools_[k]].point.transpose();
    radii_(static_cast<Eigen::Index>(k)) = tools[tools_[k]].radius;
  }
  if (!tools_.empty()) {
    solver.set_spheres(centres_, radii_);
    area_ = std::make_unique<ContactArea>(surface);
  }
}

void SurfaceSpheres::move(const FrameLoads& loads, pbd::Solver& solver) {
  if (tools_.empty()) return;
  for (size_t k = 0; k < tools_.size(); ++k)
    centres_.row(static_cast<Eigen::Index>(k)) = loads.tool_values[tools_[k]].transpose();
  solver.set_spheres(centres_, radii_);
}

void SurfaceSpheres::measure(const pbd::Solver& solver, std::vector<Eigen::Vector3d>& reactions,
                             std::vector<ToolContact>& contacts) const {
  for (size_t k = 0; k < tools_.size(); ++k) {
    reactions[tools_[k]] = solver.sphere_forces()[k];
    ToolContact& c = contacts[tools_[k]];
    c.points = static_cast<int>(solver.sphere_contacts()[k].size());
    c.area = area_->area(solver.sphere_contacts()[k]);
    c.max_penetration = solver.sphere_penetration()[k];
  }
}

}  // namespace tb
