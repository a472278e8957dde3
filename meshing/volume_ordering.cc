#include "volume_ordering.h"

#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <vector>

namespace tb {
namespace {

/// Indices 0..#rows-1 of P sorted along the Z curve of P's rows, over the box
/// [low, low + extent]^3 (ties by index).
std::vector<int> z_curve_order(const Points& P, const Eigen::RowVector3d& low, double extent) {
  const double cells = static_cast<double>((1 << 21) - 1);
  std::vector<uint64_t> key(static_cast<size_t>(P.rows()), 0);
  for (Eigen::Index i = 0; i < P.rows(); ++i) {
    uint32_t cell[3];
    for (int d = 0; d < 3; ++d) cell[d] = static_cast<uint32_t>(std::clamp((P(i, d) - low(d)) / extent, 0.0, 1.0) * cells);
    key[static_cast<size_t>(i)] = morton_key(cell[0], cell[1], cell[2]);
  }
  std::vector<int> order(key.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  std::sort(order.begin(), order.end(), [&key](int a, int b) {
    const uint64_t ka = key[static_cast<size_t>(a)], kb = key[static_cast<size_t>(b)];
    return ka != kb ? ka < kb : a < b;
  });
  return order;
}

}  // namespace

uint64_t morton_key(uint32_t x, uint32_t y, uint32_t z) {
  auto spread = [](uint64_t v) {  // the 21 low bits of v to every third bit
    v &= 0x1fffff;
    v = (v | v << 32) & 0x1f00000000ffffULL;
    v = (v | v << 16) & 0x1f0000ff0000ffULL;
    v = (v | v << 8) & 0x100f00f00f00f00fULL;
    v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
    v = (v | v << 2) & 0x1249249249249249ULL;
    return v;
  };
  return spread(x) | spread(y) << 1 | spread(z) << 2;
}

void order_along_z_curve(TetMesh& m, int fixed) {
  const Eigen::Index n = m.V.rows();
  if (fixed < 0 || fixed > n) throw std::invalid_argument("order_along_z_curve: fixed node count outside the mesh");
  if (n == 0) return;
  const Eigen::RowVector3d low = m.V.colwise().minCoeff();
  const double extent = std::max((m.V.colwise().maxCoeff() - low).maxCoeff(), 1e-300);

  // Nodes: the first `fixed` stay, the rest follow the curve.
  std::vector<int> new_index(static_cast<size_t>(n));
  for (int v = 0; v < fixed; ++v) new_index[static_cast<size_t>(v)] = v;
  const std::vector<int> moved = z_curve_order(m.V.bottomRows(n - fixed), low, extent);
  Points V = m.V;
  for (size_t k = 0; k < moved.size(); ++k) {
    const int old_node = fixed + moved[k], new_node = fixed + static_cast<int>(k);
    new_index[static_cast<size_t>(old_node)] = new_node;
    V.row(new_node) = m.V.row(old_node);
  }

  // Tets: by centroid, their nodes renamed.
  Points centroids(m.T.rows(), 3);
  for (Eigen::Index t = 0; t < m.T.rows(); ++t)
    centroids.row(t) = (m.V.row(m.T(t, 0)) + m.V.row(m.T(t, 1)) + m.V.row(m.T(t, 2)) + m.V.row(m.T(t, 3))) / 4;
  const std::vector<int> tet_order = z_curve_order(centroids, low, extent);
  Tetrahedra T(m.T.rows(), 4);
  for (size_t k = 0; k < tet_order.size(); ++k)
    for (int a = 0; a < 4; ++a)
      T(static_cast<Eigen::Index>(k), a) = new_index[static_cast<size_t>(m.T(tet_order[k], a))];
  m.V = std::move(V);
  m.T = std::move(T);
}

}  // namespace tb
