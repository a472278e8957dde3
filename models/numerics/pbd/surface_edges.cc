#include "surface_edges.h"

#include <algorithm>

namespace tb::pbd {

EdgeTriangles edge_triangles(const SurfaceMesh& s) {
  EdgeTriangles edges;
  for (Eigen::Index t = 0; t < s.F.rows(); ++t)
    for (int k = 0; k < 3; ++k) {
      const int a = s.F(t, k), b = s.F(t, (k + 1) % 3), o = s.F(t, (k + 2) % 3);
      edges[{std::min(a, b), std::max(a, b)}].push_back({{a, b, o}});
    }
  return edges;
}

}  // namespace tb::pbd
