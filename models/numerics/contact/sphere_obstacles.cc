#include "sphere_obstacles.h"

#include <algorithm>

namespace tb {

void SphereObstacles::record(const std::vector<NodeContact>& contacts, const Eigen::Matrix3Xd& x) {
  const size_t spheres = static_cast<size_t>(radii_.size());
  force_.assign(spheres, Eigen::Vector3d::Zero());
  contact_.resize(spheres);
  for (auto& list : contact_) list.clear();
  depth_.assign(spheres, 0);
  node_forces_.clear();
  for (const NodeContact& c : contacts) {
    force_[static_cast<size_t>(c.sphere)] -= c.force;  // the body pushes the sphere back
    contact_[static_cast<size_t>(c.sphere)].push_back(c.vertex);
    node_forces_.emplace_back(c.node, c.force);
  }
  for (auto& list : contact_) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  Eigen::Vector3d n;
  for (size_t k = 0; k < spheres; ++k)
    for (int node : surface_nodes_)
      depth_[k] = std::max(depth_[k], -gap(x.col(node), static_cast<int>(k), n));
}

}  // namespace tb
