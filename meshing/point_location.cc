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

bool segment_meets_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& a,
                            const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  // Moeller and Trumbore 1997: solve p + t d = a + u e1 + v e2 by Cramer's rule.
  const Eigen::Vector3d d = q - p, e1 = b - a, e2 = c - a;
  const Eigen::Vector3d h = d.cross(e2);
  const double det = e1.dot(h);
  // Parallel (relative to the lengths involved, so the test is scale-free).
  if (std::abs(det) <= 1e-14 * d.norm() * e1.norm() * e2.norm()) return false;
  const double f = 1 / det;
  const Eigen::Vector3d s = p - a;
  const double u = f * s.dot(h);
  if (u < 0 || u > 1) return false;
  const Eigen::Vector3d k = s.cross(e1);
  const double v = f * d.dot(k);
  if (v < 0 || u + v > 1) return false;
  const double t = f * e2.dot(k);
  return t >= 0 && t <= 1;
}

namespace {

/// The tet nearest to p (lowest index on ties), with p's barycentric weights in it.
TetEmbedding nearest_tet(const TetMesh& m, const Eigen::Vector3d& p) {
  TetEmbedding best;
  best.distance = std::numeric_limits<double>::infinity();
  auto corner = [&](Eigen::Index t, int k) -> Eigen::Vector3d { return m.V.row(m.T(t, k)).transpose(); };
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

/// p's weights in tet t, and whether t contains p (every weight >= -tolerance).
bool contains(const TetMesh& m, Eigen::Index t, const Eigen::Vector3d& p, double tolerance, Eigen::Vector4d& w) {
  auto corner = [&](int k) -> Eigen::Vector3d { return m.V.row(m.T(t, k)).transpose(); };
  w = barycentric(corner(0), corner(1), corner(2), corner(3), p);
  return w.minCoeff() >= -tolerance;
}

}  // namespace

TetEmbedding locate_point(const TetMesh& m, const Eigen::Vector3d& p, double tolerance) {
  Eigen::Vector4d w;
  for (Eigen::Index t = 0; t < m.T.rows(); ++t)
    if (contains(m, t, p, tolerance, w)) return {static_cast<int>(t), w, 0.0};
  return nearest_tet(m, p);
}

TetLocator::TetLocator(const TetMesh& mesh, double tolerance) : mesh_(mesh), tolerance_(tolerance) {
  if (mesh.T.rows() == 0) return;
  origin_ = mesh.V.colwise().minCoeff().transpose();
  const Eigen::Vector3d extent = mesh.V.colwise().maxCoeff().transpose() - origin_;
  // About two tets per cell.
  const double cells = std::max(1.0, static_cast<double>(mesh.T.rows()) / 2);
  cell_ = std::max(extent.maxCoeff() / std::cbrt(cells), 1e-300);
  for (int a = 0; a < 3; ++a) count_[a] = std::max<int64_t>(1, static_cast<int64_t>(std::ceil(extent(a) / cell_)));
  std::vector<std::vector<int>> bins(static_cast<size_t>(count_[0] * count_[1] * count_[2]));
  for (Eigen::Index t = 0; t < mesh.T.rows(); ++t) {
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = -lo;
    double longest = 0;
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector3d v = mesh.V.row(mesh.T(t, k)).transpose();
      lo = lo.cwiseMin(v);
      hi = hi.cwiseMax(v);
      for (int l = 0; l < k; ++l) longest = std::max(longest, (v - mesh.V.row(mesh.T(t, l)).transpose()).norm());
    }
    // A point whose weights are >= -tolerance lies within tolerance x (the tet's
    // height) of it: inflate the box by that, and a little for rounding.
    const double margin = (tolerance + 1e-9) * longest;
    const Eigen::Array3i first = cell_of(lo.array() - margin), last = cell_of(hi.array() + margin);
    for (int i = first(0); i <= last(0); ++i)
      for (int j = first(1); j <= last(1); ++j)
        for (int k = first(2); k <= last(2); ++k)
          bins[static_cast<size_t>((i * count_[1] + j) * count_[2] + k)].push_back(static_cast<int>(t));
  }
  start_.assign(bins.size() + 1, 0);
  for (size_t b = 0; b < bins.size(); ++b) start_[b + 1] = start_[b] + static_cast<int64_t>(bins[b].size());
  tets_.reserve(static_cast<size_t>(start_.back()));
  for (const auto& bin : bins) tets_.insert(tets_.end(), bin.begin(), bin.end());  // ascending within a bin
}

Eigen::Array3i TetLocator::cell_of(const Eigen::Array3d& p) const {
  Eigen::Array3i c;
  for (int a = 0; a < 3; ++a)
    c(a) = static_cast<int>(std::clamp<double>(std::floor((p(a) - origin_(a)) / cell_), 0, count_[a] - 1));
  return c;
}

TetEmbedding TetLocator::locate(const Eigen::Vector3d& p) const {
  if (mesh_.T.rows() == 0) return {};
  const Eigen::Array3i c = cell_of(p.array());
  const size_t bin = static_cast<size_t>((c(0) * count_[1] + c(1)) * count_[2] + c(2));
  Eigen::Vector4d w;
  for (int64_t i = start_[bin]; i < start_[bin + 1]; ++i)
    if (contains(mesh_, tets_[static_cast<size_t>(i)], p, tolerance_, w))
      return {tets_[static_cast<size_t>(i)], w, 0.0};
  return nearest_tet(mesh_, p);
}

double winding_number(const SurfaceMesh& s, const Eigen::Vector3d& p) {
  // The solid angles of the triangles, summed / 4 pi.
  double total = 0;
  for (Eigen::Index t = 0; t < s.F.rows(); ++t)
    total += triangle_solid_angle(s.V.row(s.F(t, 0)), s.V.row(s.F(t, 1)), s.V.row(s.F(t, 2)), p);
  return total / (4 * M_PI);
}

double triangle_solid_angle(const Eigen::Vector3d& a0, const Eigen::Vector3d& b0, const Eigen::Vector3d& c0,
                            const Eigen::Vector3d& p) {
  const Eigen::Vector3d a = a0 - p, b = b0 - p, c = c0 - p;
  const double la = a.norm(), lb = b.norm(), lc = c.norm();
  const double num = a.dot(b.cross(c));
  const double den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
  return 2 * std::atan2(num, den);
}

}  // namespace tb
