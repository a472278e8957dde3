#include "load_mapping.h"

#include <cmath>
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

}  // namespace tb
