#include "flat_tet_repair.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "mesh_checks.h"

namespace tb {
namespace {

/// The ends of tet t's shortest edge, and whether it is under 1/100 of its longest.
struct ShortEdge {
  int a, b;
  bool near_coincident;
};
ShortEdge shortest_edge(const TetMesh& m, Eigen::Index t) {
  static constexpr std::array<std::array<int, 2>, 6> kEdges{{{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}}};
  double shortest = std::numeric_limits<double>::infinity(), longest = 0;
  ShortEdge e{-1, -1, false};
  for (const auto& [i, j] : kEdges) {
    const double l = (m.V.row(m.T(t, i)) - m.V.row(m.T(t, j))).norm();
    longest = std::max(longest, l);
    if (l < shortest) {
      shortest = l;
      e.a = m.T(t, i);
      e.b = m.T(t, j);
    }
  }
  e.near_coincident = shortest < 0.01 * longest;
  return e;
}

/// Removes the merged nodes; the others keep their order.
void drop_merged_nodes(TetMesh& m, const std::vector<char>& merged_away) {
  std::vector<int> new_index(merged_away.size(), -1);
  int kept = 0;
  for (size_t v = 0; v < merged_away.size(); ++v)
    if (!merged_away[v]) {
      m.V.row(kept) = m.V.row(static_cast<Eigen::Index>(v));
      new_index[v] = kept++;
    }
  m.V.conservativeResize(kept, 3);
  for (Eigen::Index t = 0; t < m.T.rows(); ++t)
    for (int k = 0; k < 4; ++k) m.T(t, k) = new_index[static_cast<size_t>(m.T(t, k))];
}

}  // namespace

InteriorPointMerges merge_near_coincident_interior_points(TetMesh& m, int fixed_nodes) {
  const double flat_bound = flat_tet_volume_bound(bounding_box_diagonal(m.V));
  std::vector<char> merged_away(static_cast<size_t>(m.V.rows()), 0), refused(merged_away);
  std::vector<std::vector<int>> node_tets(static_cast<size_t>(m.V.rows()));
  for (Eigen::Index t = 0; t < m.T.rows(); ++t)
    for (int k = 0; k < 4; ++k) node_tets[static_cast<size_t>(m.T(t, k))].push_back(static_cast<int>(t));
  std::vector<char> removed(static_cast<size_t>(m.T.rows()), 0);
  auto holds = [&](int t, int v) { return (m.T.row(t).array() == v).any(); };

  InteriorPointMerges done;
  for (Eigen::Index t = 0; t < m.T.rows(); ++t) {
    if (removed[static_cast<size_t>(t)]) continue;
    const ShortEdge e = shortest_edge(m, t);
    if (!e.near_coincident) continue;
    const int a = std::min(e.a, e.b), b = std::max(e.a, e.b);  // keep the lower: surface vertices come first
    if (b < fixed_nodes) continue;
    // Node b moved onto node a: its tets without a must stay positive and not flat.
    // Then the tets of a over b's link fill what b's tets filled, once (their
    // boundary is b's link too), so the mesh stays a tetrahedralisation of the same
    // body; that needs the tets' orientation consistent beforehand, flat ones included
    // (TetGen writes them so, and FlatTets::Keep leaves them as written).
    bool folds = false;
    for (int u : node_tets[static_cast<size_t>(b)]) {
      if (removed[static_cast<size_t>(u)] || holds(u, a)) continue;
      Eigen::Matrix<double, 4, 3> p;
      for (int k = 0; k < 4; ++k) p.row(k) = m.V.row(m.T(u, k) == b ? a : m.T(u, k));
      folds = folds || tet_volume(p.row(0), p.row(1), p.row(2), p.row(3)) <= flat_bound;
    }
    if (folds) {
      refused[static_cast<size_t>(b)] = 1;  // may still merge from a later tet
      continue;
    }
    for (int u : node_tets[static_cast<size_t>(b)]) {
      if (removed[static_cast<size_t>(u)]) continue;
      if (holds(u, a)) {
        removed[static_cast<size_t>(u)] = 1;  // spanned the pair: gone
        continue;
      }
      for (int k = 0; k < 4; ++k)
        if (m.T(u, k) == b) m.T(u, k) = a;
      node_tets[static_cast<size_t>(a)].push_back(u);
    }
    node_tets[static_cast<size_t>(b)].clear();
    merged_away[static_cast<size_t>(b)] = 1;
    ++done.merged;
  }
  for (size_t v = 0; v < refused.size(); ++v) done.refused += refused[v] && !merged_away[v];
  if (done.merged == 0) return done;
  Eigen::Index kept = 0;
  for (Eigen::Index t = 0; t < m.T.rows(); ++t)
    if (!removed[static_cast<size_t>(t)]) m.T.row(kept++) = m.T.row(t);
  m.T.conservativeResize(kept, 4);
  drop_merged_nodes(m, merged_away);
  return done;
}

}  // namespace tb
