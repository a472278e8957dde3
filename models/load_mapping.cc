#include "load_mapping.h"

#include <Eigen/Dense>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "point_location.h"

namespace tb {
namespace {

LoadStencil from_embedding(const TetMesh& mesh, const TetEmbedding& e) {
  LoadStencil s;
  for (int k = 0; k < 4; ++k) s.nodes(k) = mesh.T(e.tet, k);
  s.weights = e.weights;
  s.distance = e.distance;
  return s;
}

}  // namespace

LoadStencil containing_tet(const TetMesh& mesh, const Eigen::Vector3d& point, const std::string& mesh_name) {
  const TetEmbedding e = locate_point(mesh, point, 1e-6);
  if (e.tet < 0 || e.distance > 0) {
    std::ostringstream msg;
    msg << "load point (" << point.x() << ", " << point.y() << ", " << point.z() << ") is outside the " << mesh_name
        << " (distance " << e.distance << " m)";
    throw std::invalid_argument(msg.str());
  }
  return from_embedding(mesh, e);
}

LoadStencil nearest_tet(const TetMesh& mesh, const Eigen::Vector3d& point) {
  if (mesh.T.rows() == 0) throw std::invalid_argument("load point: the mesh has no tetrahedra");
  return from_embedding(mesh, locate_point(mesh, point));
}

LoadStencil nearest_vertex(const Points& V, const Eigen::Vector3d& point) {
  if (V.rows() == 0) throw std::invalid_argument("load point: the mesh has no vertices");
  Eigen::Index best = 0;
  const double d2 = (V.rowwise() - point.transpose()).rowwise().squaredNorm().minCoeff(&best);
  LoadStencil s;
  s.nodes.setConstant(static_cast<int>(best));
  s.weights << 1, 0, 0, 0;
  s.distance = std::sqrt(d2);
  return s;
}

LoadStencil nearest_surface_point(const SurfaceMesh& surface, const Eigen::Vector3d& point) {
  if (surface.F.rows() == 0) throw std::invalid_argument("load point: the surface has no triangles");
  LoadStencil best;
  best.distance = std::numeric_limits<double>::infinity();
  for (Eigen::Index f = 0; f < surface.F.rows(); ++f) {
    const Eigen::Vector3d a = surface.V.row(surface.F(f, 0)), b = surface.V.row(surface.F(f, 1)),
                          c = surface.V.row(surface.F(f, 2));
    const Eigen::Vector3d q = closest_point_on_triangle(point, a, b, c);
    const double d = (q - point).norm();
    if (d >= best.distance) continue;
    // Barycentric weights of q: minimise |a + s (b - a) + t (c - a) - q| (exact for
    // q in the triangle's plane), clamped against rounding, renormalised.
    Eigen::Matrix<double, 3, 2> E;
    E << b - a, c - a;
    const Eigen::Vector2d st = (E.transpose() * E).ldlt().solve(E.transpose() * (q - a));
    Eigen::Vector3d w(1 - st.sum(), st(0), st(1));
    w = w.cwiseMax(0.0);
    if (!(w.sum() > 0) || !w.allFinite()) {  // a degenerate (zero-area) triangle: its nearest corner
      Eigen::Index k = 0;
      Eigen::Vector3d((a - q).squaredNorm(), (b - q).squaredNorm(), (c - q).squaredNorm()).minCoeff(&k);
      w = Eigen::Vector3d::Unit(k);
    }
    w /= w.sum();
    best.nodes << surface.F(f, 0), surface.F(f, 1), surface.F(f, 2), surface.F(f, 0);
    best.weights << w, 0;
    best.distance = d;
  }
  return best;
}

}  // namespace tb
