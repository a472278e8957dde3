// Rigid frictionless spheres enforced inside a nonlinear solve: the static Newton
// solve (an active set of multipliers on the gap, newton_solve.cc) and the real-time
// steppers (vbd, xpbd_neo, pd: tet_time_stepping.h). What they share: the spheres
// of the frame, the body nodes the spheres act on (the fine-volume nodes of the
// surface vertices), the gap g(x) = |x - c| - r and its normal, and what a frame
// reports per sphere (its force, the vertices in contact, the deepest penetration),
// in the currency of SphereContact (the linear FEM's, sphere_contact.h), so that the
// fine FEM reads every solve's contact alike (docs/equations.md, "Contact with a
// rigid sphere").
#pragma once

#include <Eigen/Core>
#include <utility>
#include <vector>

namespace tb {

/// The gap of a point x to the sphere (c, r), |x - c| - r (m), and its outward
/// normal (x - c) / |x - c| (+z at the centre itself, where it is undefined).
inline double sphere_gap(const Eigen::Vector3d& x, const Eigen::Vector3d& c, double r, Eigen::Vector3d& normal) {
  const Eigen::Vector3d d = x - c;
  const double len = d.norm();
  normal = len > 0 ? Eigen::Vector3d(d / len) : Eigen::Vector3d::UnitZ();
  return len - r;
}

/// A node's contact with one sphere: the body node, its surface vertex, the sphere,
/// and the force the sphere exerts on the body there (N).
struct NodeContact {
  int node = 0, vertex = 0, sphere = 0;
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
};

class SphereObstacles {
 public:
  ///   surface_nodes  the body node of each surface vertex (#surface vertices)
  explicit SphereObstacles(std::vector<int> surface_nodes) : surface_nodes_(std::move(surface_nodes)) {}

  /// This frame's spheres: centres #S by 3, radii #S. No allocation once #S is set.
  void set(const Eigen::MatrixX3d& centres, const Eigen::VectorXd& radii) {
    centres_ = centres;
    radii_ = radii;
  }
  int spheres() const { return static_cast<int>(radii_.size()); }
  const Eigen::MatrixX3d& centres() const { return centres_; }
  const Eigen::VectorXd& radii() const { return radii_; }
  const std::vector<int>& surface_nodes() const { return surface_nodes_; }

  /// The gap of a point x to sphere k and its normal (sphere_gap).
  double gap(const Eigen::Vector3d& x, int k, Eigen::Vector3d& normal) const {
    return sphere_gap(x, centres_.row(k).transpose(), radii_(k), normal);
  }

  /// After a solve: the contacts it found (the force on the body at each) and the
  /// node positions (3 by #nodes) give each sphere's force (minus the sum of its
  /// contacts'), its contact vertices (ascending) and the deepest surface vertex
  /// inside it (m, 0 if none).
  void record(const std::vector<NodeContact>& contacts, const Eigen::Matrix3Xd& x);

  const std::vector<Eigen::Vector3d>& forces() const { return force_; }
  const std::vector<std::vector<int>>& contact_vertices() const { return contact_; }
  const std::vector<double>& penetration() const { return depth_; }
  /// The contact forces on the body, (node, N), for the reactions of the support and the other tools.
  const std::vector<std::pair<int, Eigen::Vector3d>>& node_forces() const { return node_forces_; }

 private:
  std::vector<int> surface_nodes_;
  Eigen::MatrixX3d centres_;
  Eigen::VectorXd radii_;
  std::vector<Eigen::Vector3d> force_;
  std::vector<std::vector<int>> contact_;
  std::vector<double> depth_;
  std::vector<std::pair<int, Eigen::Vector3d>> node_forces_;
};

}  // namespace tb
