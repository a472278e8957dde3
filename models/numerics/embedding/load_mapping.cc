#include "load_mapping.h"

#include <Eigen/Dense>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <unordered_map>
#include <algorithm>

#include "point_location.h"

namespace tb {
namespace {

}  // namespace

NodalWeights tet_nodal_weights(const TetMesh& mesh, const TetEmbedding& e) {
  NodalWeights s;
  s.nodes = mesh.T.row(e.tet).transpose();
  s.weights = e.weights;
  s.distance = e.distance;
  return s;
}

NodalWeights containing_tet(const TetMesh& mesh, const Eigen::Vector3d& point, const std::string& mesh_name) {
  const TetEmbedding e = locate_point(mesh, point, 1e-6);
  if (e.tet < 0 || e.distance > 0) {
    std::ostringstream msg;
    msg << "load point (" << point.x() << ", " << point.y() << ", " << point.z() << ") is outside the " << mesh_name
        << " (distance " << e.distance << " m)";
    throw std::invalid_argument(msg.str());
  }
  return tet_nodal_weights(mesh, e);
}

NodalWeights nearest_tet(const TetMesh& mesh, const Eigen::Vector3d& point) {
  if (mesh.T.rows() == 0) throw std::invalid_argument("load point: the mesh has no tetrahedra");
  return tet_nodal_weights(mesh, locate_point(mesh, point));
}

NodalWeights nearest_vertex(const Points& V, const Eigen::Vector3d& point) {
  if (V.rows() == 0) throw std::invalid_argument("load point: the mesh has no vertices");
  Eigen::Index best = 0;
  const double d2 = (V.rowwise() - point.transpose()).rowwise().squaredNorm().minCoeff(&best);
  NodalWeights s;
  s.nodes.setConstant(4, static_cast<int>(best));
  s.weights = Eigen::Vector4d(1, 0, 0, 0);
  s.distance = std::sqrt(d2);
  return s;
}

NodalWeights nearest_surface_point(const SurfaceMesh& surface, const Eigen::Vector3d& point) {
  if (surface.F.rows() == 0) throw std::invalid_argument("load point: the surface has no triangles");
  NodalWeights best;
  best.nodes.resize(4);
  best.weights.resize(4);
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

NodalWeights nodal_masses(const TetMesh& mesh, double density) {
  NodalWeights m;
  m.nodes = Eigen::VectorXi::LinSpaced(mesh.V.rows(), 0, static_cast<int>(mesh.V.rows()) - 1);
  m.weights = Eigen::VectorXd::Zero(mesh.V.rows());
  for (Eigen::Index t = 0; t < mesh.T.rows(); ++t) {
    const Eigen::Vector3d a = mesh.V.row(mesh.T(t, 0)), b = mesh.V.row(mesh.T(t, 1)), c = mesh.V.row(mesh.T(t, 2)),
                          d = mesh.V.row(mesh.T(t, 3));
    const double quarter_mass = density * std::abs((b - a).dot((c - a).cross(d - a))) / 24.0;
    for (int k = 0; k < 4; ++k) m.weights(mesh.T(t, k)) += quarter_mass;
  }
  return m;
}

NodalWeights combine(const std::vector<NodalWeights>& parts, const std::vector<double>& scale) {
  if (parts.size() != scale.size()) throw std::invalid_argument("combine: one scale per part expected");
  std::vector<int> nodes;
  std::vector<double> weights;
  std::unordered_map<int, size_t> slot;
  NodalWeights out;
  for (size_t j = 0; j < parts.size(); ++j) {
    out.distance = std::max(out.distance, parts[j].distance);
    for (Eigen::Index k = 0; k < parts[j].size(); ++k) {
      const auto [it, added] = slot.emplace(parts[j].nodes(k), nodes.size());
      if (added) {
        nodes.push_back(parts[j].nodes(k));
        weights.push_back(0.0);
      }
      weights[it->second] += scale[j] * parts[j].weights(k);
    }
  }
  out.nodes = Eigen::Map<const Eigen::VectorXi>(nodes.data(), static_cast<Eigen::Index>(nodes.size()));
  out.weights = Eigen::Map<const Eigen::VectorXd>(weights.data(), static_cast<Eigen::Index>(weights.size()));
  return out;
}

}  // namespace tb
