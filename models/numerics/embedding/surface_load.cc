#include "surface_load.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "mesh_checks.h"
#include "point_location.h"

namespace tb {
namespace {

std::string point_text(const Eigen::Vector3d& p) {
  std::ostringstream os;
  os << "(" << p.x() << ", " << p.y() << ", " << p.z() << ")";
  return os.str();
}

Eigen::Vector3d corner(const SurfaceMesh& s, Eigen::Index t, int k) { return s.V.row(s.F(t, k)).transpose(); }

}  // namespace

std::vector<LoadPoint> point_load_points(const TetMesh& volume, const Eigen::Vector3d& point) {
  const TetEmbedding e = locate_point(volume, point, 1e-6);
  if (e.tet < 0 || e.distance > 0) {
    std::ostringstream msg;
    msg << "load point " << point_text(point) << " is outside the mesh (distance " << e.distance << " m)";
    throw std::invalid_argument(msg.str());
  }
  return {LoadPoint{e, point, 1.0}};
}

void gauss_legendre_01(int n, std::vector<double>& points, std::vector<double>& weights) {
  if (n < 1) throw std::invalid_argument("Gauss-Legendre: at least one point");
  points.assign(static_cast<size_t>(n), 0);
  weights.assign(static_cast<size_t>(n), 0);
  for (int i = 0; i < n; ++i) {
    // Newton on P_n from the Chebyshev-like first guess (Numerical Recipes gauleg).
    double x = std::cos(M_PI * (i + 0.75) / (n + 0.5)), dp = 0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1, p1 = 0;
      for (int k = 1; k <= n; ++k) {
        const double p2 = p1;
        p1 = p0;
        p0 = ((2.0 * k - 1) * x * p1 - (k - 1.0) * p2) / k;
      }
      dp = n * (x * p0 - p1) / (x * x - 1);
      const double dx = p0 / dp;
      x -= dx;
      if (std::abs(dx) < 1e-16) break;
    }
    // [-1, 1] -> [0, 1]; ascending order.
    points[static_cast<size_t>(n - 1 - i)] = 0.5 * (1 + x);
    weights[static_cast<size_t>(n - 1 - i)] = 1 / ((1 - x * x) * dp * dp);
  }
}

std::vector<SurfaceLoadPoint> disc_surface_points(const SurfaceMesh& surface, const Eigen::Vector3d& centre,
                                                  double radius, const DiscQuadrature& quadrature) {
  if (!std::isfinite(radius) || radius <= 0) {
    std::ostringstream msg;
    msg << "disc radius " << radius << " is not a positive length (m)";
    throw std::invalid_argument(msg.str());
  }
  // The tangent plane at the centre: the triangles touching it.
  const double on_surface = 1e-9 * bounding_box_diagonal(surface.V);
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  double nearest = std::numeric_limits<double>::infinity();
  for (Eigen::Index t = 0; t < surface.F.rows(); ++t) {
    const Eigen::Vector3d a = corner(surface, t, 0), b = corner(surface, t, 1), c = corner(surface, t, 2);
    const double d = point_triangle_distance(centre, a, b, c);
    nearest = std::min(nearest, d);
    if (d <= on_surface) normal += (b - a).cross(c - a);  // area-weighted
  }
  if (normal.squaredNorm() == 0) {
    std::ostringstream msg;
    msg << "a disc load needs its point on the surface; " << point_text(centre) << " is " << nearest << " m from it";
    throw std::invalid_argument(msg.str());
  }
  normal.normalize();
  // e1: the coordinate axis least aligned with the normal, made tangent.
  Eigen::Index axis = 0;
  normal.cwiseAbs().minCoeff(&axis);
  const Eigen::Vector3d e1 = (Eigen::Vector3d::Unit(axis) - normal(axis) * normal).normalized();
  const Eigen::Vector3d e2 = normal.cross(e1);

  // Triangles the disc can reach.
  const double reach = 1.01 * radius + on_surface;
  std::vector<int> candidates;
  for (Eigen::Index t = 0; t < surface.F.rows(); ++t)
    if (point_triangle_distance(centre, corner(surface, t, 0), corner(surface, t, 1), corner(surface, t, 2)) <= reach)
      candidates.push_back(static_cast<int>(t));

  std::vector<double> s, w;
  gauss_legendre_01(quadrature.radial, s, w);
  std::vector<SurfaceLoadPoint> hits;
  double total = 0;
  for (size_t k = 0; k < s.size(); ++k)
    for (int j = 0; j < quadrature.angular; ++j) {
      const double theta = 2 * M_PI * (j + 0.5) / quadrature.angular;
      const Eigen::Vector3d q = centre + radius * s[k] * (std::cos(theta) * e1 + std::sin(theta) * e2);
      SurfaceLoadPoint best{-1, q, w[k] * s[k]};  // int_0^1 f(s) s ds; the angle's weight is uniform
      double best_d = std::numeric_limits<double>::infinity();
      for (int t : candidates) {
        const Eigen::Vector3d p =
            closest_point_on_triangle(q, corner(surface, t, 0), corner(surface, t, 1), corner(surface, t, 2));
        const double d = (p - q).norm();
        if (d < best_d) best_d = d, best.triangle = t, best.position = p;
      }
      if (best.triangle < 0 || best_d > 0.01 * radius) {
        std::ostringstream msg;
        msg << "the disc of radius " << radius << " m around " << point_text(centre)
            << " leaves the surface (its point " << point_text(q) << " is "
            << (best.triangle < 0 ? std::numeric_limits<double>::infinity() : best_d)
            << " m from it, more than 1% of the radius); use a smaller radius";
        throw std::invalid_argument(msg.str());
      }
      if (best_d <= on_surface) best.position = q;  // already on the surface: no round-off from projecting
      total += best.weight;
      hits.push_back(best);
    }
  for (SurfaceLoadPoint& h : hits) h.weight /= total;
  return hits;
}

std::vector<LoadPoint> disc_load_points(const TetMesh& volume, const SurfaceMesh& surface,
                                        const std::vector<int>& surface_to_volume, const Eigen::Vector3d& centre,
                                        double radius, const DiscQuadrature& quadrature) {
  if (surface_to_volume.size() != static_cast<size_t>(surface.V.rows()))
    throw std::invalid_argument("disc load: the fine surface has no map to the fine volume's nodes");
  const std::vector<SurfaceLoadPoint> hits = disc_surface_points(surface, centre, radius, quadrature);

  // The tet owning each hit triangle: the one whose nodes include the triangle's.
  std::vector<int> owner(static_cast<size_t>(surface.F.rows()), -1);
  std::vector<char> needed_node(static_cast<size_t>(volume.V.rows()), 0);
  std::vector<int> hit_triangles;
  for (const SurfaceLoadPoint& h : hits) {
    if (owner[static_cast<size_t>(h.triangle)] == -2) continue;
    owner[static_cast<size_t>(h.triangle)] = -2;  // wanted
    hit_triangles.push_back(h.triangle);
    for (int k = 0; k < 3; ++k)
      needed_node[static_cast<size_t>(surface_to_volume[static_cast<size_t>(surface.F(h.triangle, k))])] = 1;
  }
  for (Eigen::Index t = 0; t < volume.T.rows(); ++t) {
    int hits_in_tet = 0;
    for (int k = 0; k < 4; ++k) hits_in_tet += needed_node[static_cast<size_t>(volume.T(t, k))];
    if (hits_in_tet < 3) continue;
    for (int f : hit_triangles) {
      if (owner[static_cast<size_t>(f)] != -2) continue;
      bool all = true;
      for (int k = 0; k < 3 && all; ++k) {
        const int node = surface_to_volume[static_cast<size_t>(surface.F(f, k))];
        all = (volume.T.row(t).array() == node).any();
      }
      if (all) owner[static_cast<size_t>(f)] = static_cast<int>(t);
    }
  }
  std::vector<LoadPoint> out;
  out.reserve(hits.size());
  for (const SurfaceLoadPoint& h : hits) {
    const int tet = owner[static_cast<size_t>(h.triangle)];
    if (tet < 0)
      throw std::invalid_argument("disc load: surface triangle " + std::to_string(h.triangle) +
                                  " is not a face of any fine tet (the volume does not keep the surface)");
    TetEmbedding at;
    at.tet = tet;
    at.weights = barycentric(volume.V.row(volume.T(tet, 0)).transpose(), volume.V.row(volume.T(tet, 1)).transpose(),
                             volume.V.row(volume.T(tet, 2)).transpose(), volume.V.row(volume.T(tet, 3)).transpose(),
                             h.position);
    out.push_back({at, h.position, h.weight});
  }
  return out;
}

NodalWeights nodal_weights_p1(const TetMesh& volume, const std::vector<LoadPoint>& points) {
  std::vector<NodalWeights> parts;
  std::vector<double> scale;
  parts.reserve(points.size());
  for (const LoadPoint& p : points) {
    parts.push_back(tet_nodal_weights(volume, p.at));
    scale.push_back(p.weight);
  }
  return combine(parts, scale);
}

NodalWeights surface_nodal_weights(const SurfaceMesh& surface, const std::vector<SurfaceLoadPoint>& points) {
  std::vector<NodalWeights> parts;
  std::vector<double> scale;
  parts.reserve(points.size());
  for (const SurfaceLoadPoint& p : points) {
    const Eigen::Vector3d a = corner(surface, p.triangle, 0), b = corner(surface, p.triangle, 1),
                          c = corner(surface, p.triangle, 2);
    // Barycentric coordinates of the point in its triangle (it lies in the triangle's plane).
    const Eigen::Vector3d n = (b - a).cross(c - a);
    const double area2 = n.squaredNorm();
    NodalWeights w;
    w.nodes = surface.F.row(p.triangle).transpose();
    w.weights.resize(3);
    if (area2 > 0) {
      w.weights(1) = (p.position - a).cross(c - a).dot(n) / area2;
      w.weights(2) = (b - a).cross(p.position - a).dot(n) / area2;
      w.weights(0) = 1 - w.weights(1) - w.weights(2);
    } else {
      w.weights << 1, 0, 0;  // a degenerate triangle: its first corner
    }
    parts.push_back(std::move(w));
    scale.push_back(p.weight);
  }
  return combine(parts, scale);
}

}  // namespace tb
