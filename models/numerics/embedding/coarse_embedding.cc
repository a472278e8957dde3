#include "coarse_embedding.h"

#include "point_location.h"

namespace tb {

std::vector<ControlPoint> embed_vertices(const Points& V, const TetMesh& coarse) {
  std::vector<ControlPoint> out(static_cast<size_t>(V.rows()));
  for (Eigen::Index v = 0; v < V.rows(); ++v) {
    const TetEmbedding e = locate_point(coarse, V.row(v).transpose());
    out[static_cast<size_t>(v)] = {static_cast<int>(v), e};
  }
  return out;
}

void interpolate_embedded(const std::vector<ControlPoint>& points, const Tetrahedra& coarse_T,
                          const Eigen::VectorXd& coarse_u, Points& out) {
  if (out.rows() != static_cast<Eigen::Index>(points.size())) out.resize(static_cast<Eigen::Index>(points.size()), 3);
  for (size_t k = 0; k < points.size(); ++k) {
    const ControlPoint& cp = points[k];
    Eigen::Vector3d u = Eigen::Vector3d::Zero();
    for (int j = 0; j < 4; ++j) u += cp.coarse.weights(j) * coarse_u.segment<3>(3 * coarse_T(cp.coarse.tet, j));
    out.row(static_cast<Eigen::Index>(k)) = u.transpose();
  }
}

}  // namespace tb
