#include "winding_number_tree.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "point_location.h"

namespace tb {
namespace {

constexpr int kLeafSize = 8;

}  // namespace

WindingNumberTree::WindingNumberTree(const SurfaceMesh& surface) : surface_(surface) {
  order_.resize(static_cast<size_t>(surface.F.rows()));
  for (size_t t = 0; t < order_.size(); ++t) order_[t] = static_cast<int>(t);
  nodes_.reserve(2 * order_.size() / kLeafSize + 2);
  if (!order_.empty()) build(0, static_cast<int>(order_.size()));
}

int WindingNumberTree::build(int first, int count) {
  const Points& V = surface_.V;
  const auto& F = surface_.F;
  Node node;
  node.first = first;
  node.count = count;
  double area = 0;
  Eigen::Vector3d weighted = Eigen::Vector3d::Zero(), lo = Eigen::Vector3d::Constant(INFINITY),
                  hi = Eigen::Vector3d::Constant(-INFINITY);
  node.dipole.setZero();
  for (int i = first; i < first + count; ++i) {
    const int t = order_[static_cast<size_t>(i)];
    const Eigen::Vector3d a = V.row(F(t, 0)), b = V.row(F(t, 1)), c = V.row(F(t, 2));
    const Eigen::Vector3d n = 0.5 * (b - a).cross(c - a);
    node.dipole += n;
    area += n.norm();
    weighted += n.norm() * (a + b + c) / 3;
    for (const Eigen::Vector3d* v : {&a, &b, &c}) {
      lo = lo.cwiseMin(*v);
      hi = hi.cwiseMax(*v);
    }
  }
  node.centre = area > 0 ? Eigen::Vector3d(weighted / area) : Eigen::Vector3d(0.5 * (lo + hi));
  for (int i = first; i < first + count; ++i)
    for (int k = 0; k < 3; ++k)
      node.radius =
          std::max(node.radius, (V.row(F(order_[static_cast<size_t>(i)], k)).transpose() - node.centre).norm());
  const int index = static_cast<int>(nodes_.size());
  nodes_.push_back(node);
  if (count > kLeafSize) {
    // Split at the median of the triangles' centroids along the box's longest axis.
    int axis;
    (hi - lo).maxCoeff(&axis);
    auto centroid = [&](int t) { return V(F(t, 0), axis) + V(F(t, 1), axis) + V(F(t, 2), axis); };
    const auto begin = order_.begin() + first, middle = begin + count / 2, end = begin + count;
    std::nth_element(begin, middle, end, [&](int a, int b) {
      const double ca = centroid(a), cb = centroid(b);
      return ca < cb || (ca == cb && a < b);  // total order: deterministic
    });
    const int left = build(first, count / 2);
    const int right = build(first + count / 2, count - count / 2);
    nodes_[static_cast<size_t>(index)].children[0] = left;
    nodes_[static_cast<size_t>(index)].children[1] = right;
  }
  return index;
}

double WindingNumberTree::exact(int first, int count, const Eigen::Vector3d& p) const {
  // Van Oosterom-Strackee solid angles, as winding_number() (point_location.h).
  double total = 0;
  for (int i = first; i < first + count; ++i) {
    const int t = order_[static_cast<size_t>(i)];
    total += triangle_solid_angle(surface_.V.row(surface_.F(t, 0)), surface_.V.row(surface_.F(t, 1)),
                                  surface_.V.row(surface_.F(t, 2)), p);
  }
  return total / (4 * M_PI);
}

double WindingNumberTree::operator()(const Eigen::Vector3d& p) const {
  if (nodes_.empty()) return 0;
  double total = 0;
  int stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& n = nodes_[static_cast<size_t>(stack[--top])];
    const Eigen::Vector3d r = n.centre - p;
    const double distance = r.norm();
    if (distance > kFarFactor * n.radius) {
      total += n.dipole.dot(r) / (4 * M_PI * distance * distance * distance);  // the cluster's dipole
    } else if (n.children[0] < 0) {
      total += exact(n.first, n.count, p);
    } else {
      stack[top++] = n.children[0];
      stack[top++] = n.children[1];
    }
  }
  return total;
}

}  // namespace tb
