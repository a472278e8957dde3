#include "point_location.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

#include "mesh_checks.h"

namespace tb {

Eigen::Vector4d barycentric(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                            const Eigen::Vector3d& d, const Eigen::Vector3d& p) {
  Eigen::Matrix3d M;
  M << b - a, c - a, d - a;
  const Eigen::Vector3d l = M.partialPivLu().solve(p - a);
  return {1 - l.sum(), l(0), l(1), l(2)};
}

Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                          const Eigen::Vector3d& c) {
  // Ericson, Real-Time Collision Detection, 5.1.5: closest point on a triangle.
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + d1 / (d1 - d3) * ab;
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + d2 / (d2 - d6) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  const double denom = 1 / (va + vb + vc);
  return a + ab * vb * denom + ac * vc * denom;
}

double point_triangle_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                               const Eigen::Vector3d& c) {
  return (p - closest_point_on_triangle(p, a, b, c)).norm();
}

TetEmbedding locate_point(const TetMesh& m, const Eigen::Vector3d& p, double tolerance) {
  TetEmbedding best;
  best.distance = std::numeric_limits<double>::infinity();
  const double eps = tolerance;
  auto corner = [&](Eigen::Index t, int k) -> Eigen::Vector3d { return m.V.row(m.T(t, k)).transpose(); };
  for (Eigen::Index t = 0; t < m.T.rows(); ++t) {
    const Eigen::Vector4d w = barycentric(corner(t, 0), corner(t, 1), corner(t, 2), corner(t, 3), p);
    if (w.minCoeff() >= -eps) return {static_cast<int>(t), w, 0.0};
  }
  for (Eigen::Index t = 0; t < m.T.rows(); ++t) {
    static const int faces[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
    double dist = std::numeric_limits<double>::infinity();
    for (const auto& f : faces)
      dist = std::min(dist, point_triangle_distance(p, corner(t, f[0]), corner(t, f[1]), corner(t, f[2])));
    if (dist < best.distance) {
      best.tet = static_cast<int>(t);
      best.distance = dist;
    }
  }
  if (best.tet >= 0) {
    const Eigen::Index t = best.tet;
    best.weights = barycentric(corner(t, 0), corner(t, 1), corner(t, 2), corner(t, 3), p);
  }
  return best;
}

double winding_number(const SurfaceMesh& s, const Eigen::Vector3d& p) {
  // Van Oosterom-Strackee solid angle of each triangle, summed / 4 pi.
  double total = 0;
  for (Eigen::Index t = 0; t < s.F.rows(); ++t) {
    const Eigen::Vector3d a = s.V.row(s.F(t, 0)).transpose() - p, b = s.V.row(s.F(t, 1)).transpose() - p,
                          c = s.V.row(s.F(t, 2)).transpose() - p;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double num = a.dot(b.cross(c));
    const double den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    total += 2 * std::atan2(num, den);
  }
  return total / (4 * M_PI);
}

}  // namespace tb
