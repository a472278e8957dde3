#include "coarse_mesh.h"

#include <algorithm>
#include <array>
#include <limits>
#include <map>
#include <set>

#include "mesh_checks.h"
#include "point_location.h"
#include "tetgen_driver.h"
#include "winding_number_tree.h"

namespace tb {
namespace {

using Face = std::array<int, 3>;
using Edge = std::pair<int, int>;

/// Face k of a tet is the one opposite its node k.
constexpr int kFaceNodes[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};

Face face_key(const TetMesh& m, Eigen::Index t, int k) {
  Face f{m.T(t, kFaceNodes[k][0]), m.T(t, kFaceNodes[k][1]), m.T(t, kFaceNodes[k][2])};
  std::sort(f.begin(), f.end());
  return f;
}
Edge edge_key(int a, int b) { return {std::min(a, b), std::max(a, b)}; }

/// The boundary of a tet mesh: faces in one tet, and the edges and nodes on them.
struct Boundary {
  std::map<Face, int> face_tets;
  std::set<Edge> edges;
  std::vector<char> nodes;
  explicit Boundary(const TetMesh& m) : nodes(static_cast<size_t>(m.V.rows()), 0) {
    for (Eigen::Index t = 0; t < m.T.rows(); ++t)
      for (int k = 0; k < 4; ++k) ++face_tets[face_key(m, t, k)];
    for (const auto& [f, n] : face_tets)
      if (n == 1)
        for (int i = 0; i < 3; ++i) {
          nodes[static_cast<size_t>(f[static_cast<size_t>(i)])] = 1;
          edges.insert(edge_key(f[static_cast<size_t>(i)], f[static_cast<size_t>((i + 1) % 3)]));
        }
  }
  bool on_boundary(const TetMesh& m, Eigen::Index t, int k) const { return face_tets.at(face_key(m, t, k)) == 1; }
};

/// Whether removing tet t keeps the boundary a 2-manifold and every node in a tet.
/// Two boundary faces (opposite nodes i, j): the edge (i, j) becomes boundary, so it
/// must not be already. One boundary face (opposite node i): node i becomes
/// boundary, so it must not be already. Three or four: a node would be left alone.
bool removable(const TetMesh& m, const Boundary& b, Eigen::Index t) {
  std::vector<int> opposite;  // nodes opposite the boundary faces
  for (int k = 0; k < 4; ++k)
    if (b.on_boundary(m, t, k)) opposite.push_back(m.T(t, k));
  if (opposite.size() == 2) return !b.edges.count(edge_key(opposite[0], opposite[1]));
  if (opposite.size() == 1) return !b.nodes[static_cast<size_t>(opposite[0])];
  return false;
}

/// Tets below `degrees`, worst first (ties by index).
std::vector<std::pair<double, Eigen::Index>> slivers_of(const TetMesh& m, double degrees) {
  std::vector<std::pair<double, Eigen::Index>> out;
  for (Eigen::Index t = 0; t < m.T.rows(); ++t)
    if (const double q = tet_min_dihedral_deg(m, t); q < degrees) out.emplace_back(q, t);
  std::sort(out.begin(), out.end());
  return out;
}

/// Keeps the tets in `keep` and the nodes they use (renumbered in their old order).
///   new_index  #m.V: the new index of each old node, -1 if dropped
TetMesh compact(const TetMesh& m, const std::vector<int>& keep, std::vector<int>& new_index) {
  new_index.assign(static_cast<size_t>(m.V.rows()), -1);
  for (int t : keep)
    for (int k = 0; k < 4; ++k) new_index[static_cast<size_t>(m.T(t, k))] = 0;
  int next = 0;
  for (auto& n : new_index)
    if (n == 0) n = next++;
  TetMesh out;
  out.V.resize(next, 3);
  for (Eigen::Index v = 0; v < m.V.rows(); ++v)
    if (new_index[static_cast<size_t>(v)] >= 0) out.V.row(new_index[static_cast<size_t>(v)]) = m.V.row(v);
  out.T.resize(static_cast<Eigen::Index>(keep.size()), 4);
  for (size_t i = 0; i < keep.size(); ++i)
    for (int k = 0; k < 4; ++k)
      out.T(static_cast<Eigen::Index>(i), k) = new_index[static_cast<size_t>(m.T(keep[i], k))];
  return out;
}

/// The Delaunay mesh of V[selected] less the tets whose centroid is outside the
/// surface (a Delaunay mesh fills the convex hull), flat boundary slivers removed.
CoarseMesh mesh_selection(const Points& V, const std::vector<int>& selected, const WindingNumberTree& winding_number,
                          double min_dihedral_deg, const std::string& source) {
  Points points(static_cast<Eigen::Index>(selected.size()), 3);
  for (size_t i = 0; i < selected.size(); ++i) points.row(static_cast<Eigen::Index>(i)) = V.row(selected[i]);
  const TetMesh hull = tetrahedralize_points(points, source);
  std::vector<int> inside;
  for (Eigen::Index t = 0; t < hull.T.rows(); ++t) {
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (int k = 0; k < 4; ++k) centroid += hull.V.row(hull.T(t, k)).transpose() / 4.0;
    if (winding_number(centroid) > 0.5) inside.push_back(static_cast<int>(t));
  }
  CoarseMesh c;
  std::vector<int> new_index;
  c.mesh = compact(hull, inside, new_index);
  c.node_vertex.assign(static_cast<size_t>(c.mesh.V.rows()), -1);
  for (size_t i = 0; i < selected.size(); ++i)
    if (new_index[i] >= 0) c.node_vertex[static_cast<size_t>(new_index[i])] = selected[i];
  if (min_dihedral_deg > 0) c.repair.boundary_slivers_removed = remove_flat_boundary_slivers(c.mesh, min_dihedral_deg);
  c.repair.slivers_left = count_tets_below_dihedral(c.mesh, min_dihedral_deg);
  return c;
}

/// Smallest dihedral angle of the tets `star` with node n placed at p; -1 if one inverts.
double star_quality(const TetMesh& m, const std::vector<int>& star, int n, const Eigen::Vector3d& p) {
  double q = 180;
  for (int t : star) {
    std::array<Eigen::Vector3d, 4> c;
    for (int k = 0; k < 4; ++k) c[static_cast<size_t>(k)] = m.T(t, k) == n ? p : Eigen::Vector3d(m.V.row(m.T(t, k)));
    if (tet_volume(c[0], c[1], c[2], c[3]) <= 0) return -1;
    q = std::min(q, tet_min_dihedral_deg(c[0], c[1], c[2], c[3]));
  }
  return q;
}

constexpr int kCorner = 0, kInterior = 3;  ///< selection classes (hybrid_builder.cc)

/// One round of moves: for each sliver, worst first, the (node, fine vertex) swap
/// that most improves the smallest angle around the node (fine vertices of the
/// node's class within `spacing`, the selection's coverage radius); if none
/// improves it, an interior node of the sliver is left out. A node changes once
/// per round. Returns the new selection (sorted); `moves`, `drops` count.
std::vector<int> perturbed_selection(const CoarseMesh& c, const Points& V, const std::vector<int>& priority,
                                     const std::vector<int>& selected, double spacing, double min_dihedral_deg,
                                     int& moves, int& drops) {
  const TetMesh& m = c.mesh;
  std::vector<std::vector<int>> star(static_cast<size_t>(m.V.rows()));
  for (Eigen::Index t = 0; t < m.T.rows(); ++t)
    for (int k = 0; k < 4; ++k) star[static_cast<size_t>(m.T(t, k))].push_back(static_cast<int>(t));
  std::vector<char> taken(static_cast<size_t>(V.rows()), 0);  // selected, or chosen this round
  for (int v : selected) taken[static_cast<size_t>(v)] = 1;
  std::vector<char> moved(static_cast<size_t>(m.V.rows()), 0);
  std::vector<int> out = selected;
  const double radius2 = spacing * spacing;
  moves = drops = 0;
  for (const auto& [quality, t] : slivers_of(m, min_dihedral_deg)) {
    double best_score = -std::numeric_limits<double>::infinity();
    int best_node = -1, best_vertex = -1;
    for (int k = 0; k < 4; ++k) {
      const int n = m.T(t, k), f = c.node_vertex[static_cast<size_t>(n)];
      if (moved[static_cast<size_t>(n)] || priority[static_cast<size_t>(f)] == kCorner) continue;  // corners stay
      const std::vector<int>& s = star[static_cast<size_t>(n)];
      const double now = star_quality(m, s, n, V.row(f).transpose());
      for (Eigen::Index g = 0; g < V.rows(); ++g) {
        if (taken[static_cast<size_t>(g)] || priority[static_cast<size_t>(g)] != priority[static_cast<size_t>(f)] ||
            (V.row(g) - V.row(f)).squaredNorm() > radius2)
          continue;
        const double score = star_quality(m, s, n, V.row(g).transpose());
        if (score > now && score > best_score) {
          best_score = score;
          best_node = n;
          best_vertex = static_cast<int>(g);
        }
      }
    }
    if (best_node >= 0) {
      const int from = c.node_vertex[static_cast<size_t>(best_node)];
      *std::find(out.begin(), out.end(), from) = best_vertex;
      taken[static_cast<size_t>(best_vertex)] = 1;
      moved[static_cast<size_t>(best_node)] = 1;
      ++moves;
      continue;
    }
    // No swap helps: leave out an interior node of the sliver (not a control
    // point), the first by fine index, and let the Delaunay mesh close the gap.
    int drop = -1;
    for (int k = 0; k < 4; ++k) {
      const int n = m.T(t, k), f = c.node_vertex[static_cast<size_t>(n)];
      if (!moved[static_cast<size_t>(n)] && priority[static_cast<size_t>(f)] == kInterior &&
          (drop < 0 || f < c.node_vertex[static_cast<size_t>(drop)]))
        drop = n;
    }
    if (drop < 0) continue;
    out.erase(std::find(out.begin(), out.end(), c.node_vertex[static_cast<size_t>(drop)]));
    moved[static_cast<size_t>(drop)] = 1;
    ++drops;
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

int remove_flat_boundary_slivers(TetMesh& m, double min_dihedral_deg) {
  int removed = 0;
  for (bool again = true; again;) {
    again = false;
    const Boundary b(m);
    for (const auto& [quality, t] : slivers_of(m, min_dihedral_deg))
      if (removable(m, b, t)) {
        // Drop row t; the boundary changed, so look again from the start.
        m.T.block(t, 0, m.T.rows() - t - 1, 4) = m.T.bottomRows(m.T.rows() - t - 1).eval();
        m.T.conservativeResize(m.T.rows() - 1, 4);
        ++removed;
        again = true;
        break;
      }
  }
  return removed;
}

CoarseMesh build_coarse_mesh(const Points& V, const std::vector<int>& priority, std::vector<int> selected,
                             double spacing, const SurfaceMesh& surface, const CoarseMeshOptions& o,
                             const std::string& source) {
  std::sort(selected.begin(), selected.end());
  const WindingNumberTree winding_number(surface);  // built once for every re-mesh
  CoarseMesh best;
  double best_angle = -1;
  int moved_total = 0, dropped_total = 0;
  for (int round = 0;; ++round) {
    CoarseMesh c = mesh_selection(V, selected, winding_number, o.min_dihedral_deg, source);
    c.repair.remeshes = round;
    c.repair.vertices_moved = moved_total;
    c.repair.interior_vertices_dropped = dropped_total;
    const double angle = min_dihedral_angle_deg(c.mesh);
    if (best_angle < 0 || c.repair.slivers_left < best.repair.slivers_left ||
        (c.repair.slivers_left == best.repair.slivers_left && angle > best_angle)) {
      best = c;
      best_angle = angle;
    }
    if (c.repair.slivers_left == 0 || round >= o.max_rounds) break;
    int moves = 0, drops = 0;
    selected = perturbed_selection(c, V, priority, selected, spacing, o.min_dihedral_deg, moves, drops);
    if (moves + drops == 0 || selected.size() < 4) break;
    moved_total += moves;
    dropped_total += drops;
  }
  return best;
}

}  // namespace tb
