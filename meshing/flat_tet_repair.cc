#include "flat_tet_repair.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

#include "mesh_checks.h"

namespace tb {
namespace {

constexpr std::array<std::array<int, 2>, 6> kEdges{{{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}}};

/// The ends of tet t's shortest edge, and whether it is under 1/100 of its longest.
struct ShortEdge {
  int a, b;
  bool near_coincident;
};
ShortEdge shortest_edge(const TetMesh& m, Eigen::Index t) {
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

/// The tet mesh under repair: which tets each node is in, which tets and nodes have
/// gone. A collapse moves node b onto node a: the tets holding both go, b's other
/// tets take a in its place. It is valid when every one of those stays positively
/// oriented and not flat: then they fill what b's tets filled, once (their boundary
/// is b's link too), so the mesh stays a tetrahedralisation of the same body. That
/// needs the tets' orientation consistent beforehand, flat ones included (TetGen
/// writes them so, and FlatTets::Keep leaves them as written).
class EdgeCollapses {
 public:
  explicit EdgeCollapses(TetMesh& m)
      : m_(m),
        flat_bound_(flat_tet_volume_bound(bounding_box_diagonal(m.V))),
        node_tets_(static_cast<size_t>(m.V.rows())),
        tet_removed_(static_cast<size_t>(m.T.rows()), 0),
        node_removed_(static_cast<size_t>(m.V.rows()), 0) {
    for (Eigen::Index t = 0; t < m.T.rows(); ++t)
      for (int k = 0; k < 4; ++k) node_tets_[static_cast<size_t>(m.T(t, k))].push_back(static_cast<int>(t));
  }

  bool tet_removed(Eigen::Index t) const { return tet_removed_[static_cast<size_t>(t)] != 0; }
  bool node_removed(int v) const { return node_removed_[static_cast<size_t>(v)] != 0; }
  bool flat(Eigen::Index t) const {
    return tet_volume(m_.V.row(m_.T(t, 0)), m_.V.row(m_.T(t, 1)), m_.V.row(m_.T(t, 2)), m_.V.row(m_.T(t, 3))) <=
           flat_bound_;
  }
  std::vector<int> neighbours(int v) const {
    std::vector<int> n;
    for (int u : node_tets_[static_cast<size_t>(v)])
      for (int k = 0; k < 4; ++k)
        if (m_.T(u, k) != v) n.push_back(m_.T(u, k));
    std::sort(n.begin(), n.end());
    n.erase(std::unique(n.begin(), n.end()), n.end());
    return n;
  }

  /// The smallest volume of b's tets once b is moved onto a, over its longest edge
  /// cubed (a shape measure); empty if a tet would be inverted or flat.
  std::optional<double> quality_after(int b, int a) const {
    double worst = std::numeric_limits<double>::infinity();
    for (int u : node_tets_[static_cast<size_t>(b)]) {
      if (holds(u, a)) continue;
      Eigen::Matrix<double, 4, 3> p;
      for (int k = 0; k < 4; ++k) p.row(k) = m_.V.row(m_.T(u, k) == b ? a : m_.T(u, k));
      const double volume = tet_volume(p.row(0), p.row(1), p.row(2), p.row(3));
      if (volume <= flat_bound_) return std::nullopt;
      double longest = 0;
      for (const auto& [i, j] : kEdges) longest = std::max(longest, (p.row(i) - p.row(j)).norm());
      worst = std::min(worst, volume / (longest * longest * longest));
    }
    return worst;
  }

  void collapse(int b, int a) {
    for (int u : node_tets_[static_cast<size_t>(b)]) {
      if (holds(u, a)) {
        tet_removed_[static_cast<size_t>(u)] = 1;  // spanned the pair: gone
        for (int k = 0; k < 4; ++k) {
          if (m_.T(u, k) == b) continue;
          auto& tets = node_tets_[static_cast<size_t>(m_.T(u, k))];
          const auto listed = std::find(tets.begin(), tets.end(), u);
          assert(listed != tets.end());  // every live tet is in each of its nodes' lists
          tets.erase(listed);
        }
        continue;
      }
      for (int k = 0; k < 4; ++k)
        if (m_.T(u, k) == b) m_.T(u, k) = a;
      node_tets_[static_cast<size_t>(a)].push_back(u);
    }
    node_tets_[static_cast<size_t>(b)].clear();
    node_removed_[static_cast<size_t>(b)] = 1;
  }

  /// Drops the removed tets and nodes; the others keep their order.
  void compact() {
    Eigen::Index kept = 0;
    for (Eigen::Index t = 0; t < m_.T.rows(); ++t)
      if (!tet_removed(t)) m_.T.row(kept++) = m_.T.row(t);
    m_.T.conservativeResize(kept, 4);
    std::vector<int> new_index(node_removed_.size(), -1);
    int kept_nodes = 0;
    for (size_t v = 0; v < node_removed_.size(); ++v)
      if (!node_removed_[v]) {
        m_.V.row(kept_nodes) = m_.V.row(static_cast<Eigen::Index>(v));
        new_index[v] = kept_nodes++;
      }
    m_.V.conservativeResize(kept_nodes, 3);
    for (Eigen::Index t = 0; t < m_.T.rows(); ++t)
      for (int k = 0; k < 4; ++k) m_.T(t, k) = new_index[static_cast<size_t>(m_.T(t, k))];
  }

 private:
  bool holds(int t, int v) const { return (m_.T.row(t).array() == v).any(); }

  TetMesh& m_;
  double flat_bound_;
  std::vector<std::vector<int>> node_tets_;
  std::vector<char> tet_removed_, node_removed_;
};

/// First pass: near-coincident points, in tet order. Flags in `refused` the points
/// whose merge was refused.
void merge_near_coincident(EdgeCollapses& c, const TetMesh& m, int fixed_nodes, InteriorPointMerges& done,
                           std::vector<char>& refused) {
  for (Eigen::Index t = 0; t < m.T.rows(); ++t) {
    if (c.tet_removed(t)) continue;
    const ShortEdge e = shortest_edge(m, t);
    if (!e.near_coincident) continue;
    const int a = std::min(e.a, e.b), b = std::max(e.a, e.b);  // keep the lower: surface vertices come first
    if (b < fixed_nodes) continue;
    if (!c.quality_after(b, a)) {
      refused[static_cast<size_t>(b)] = 1;  // may still merge from a later tet
      continue;
    }
    c.collapse(b, a);
    ++done.merged;
  }
}

/// Second pass: a flat tet left keeps an interior point whose merge was refused, or
/// had no near-coincident edge. One of its interior points is collapsed into the
/// neighbour that leaves its tets best shaped (ties: the first found), if any is valid.
void collapse_into_flat_tets_best_neighbour(EdgeCollapses& c, const TetMesh& m, int fixed_nodes,
                                            InteriorPointMerges& done) {
  for (Eigen::Index t = 0; t < m.T.rows(); ++t) {
    if (c.tet_removed(t) || !c.flat(t)) continue;
    double best_quality = 0;
    int best_b = -1, best_a = -1;
    for (int k = 0; k < 4; ++k) {
      const int b = m.T(t, k);
      if (b < fixed_nodes) continue;
      for (int a : c.neighbours(b)) {
        const std::optional<double> q = c.quality_after(b, a);
        if (q && *q > best_quality) {
          best_quality = *q;
          best_b = b;
          best_a = a;
        }
      }
    }
    if (best_b < 0) continue;  // for the mesh check to report
    c.collapse(best_b, best_a);
    ++done.flat_tets_collapsed;
  }
}

}  // namespace

InteriorPointMerges merge_near_coincident_interior_points(TetMesh& m, int fixed_nodes) {
  EdgeCollapses c(m);
  InteriorPointMerges done;
  std::vector<char> refused(static_cast<size_t>(m.V.rows()), 0);
  merge_near_coincident(c, m, fixed_nodes, done, refused);
  collapse_into_flat_tets_best_neighbour(c, m, fixed_nodes, done);
  for (size_t v = 0; v < refused.size(); ++v)  // still there after both passes
    done.refused += refused[v] && !c.node_removed(static_cast<int>(v));
  if (done.merged + done.flat_tets_collapsed > 0) c.compact();
  return done;
}

}  // namespace tb
