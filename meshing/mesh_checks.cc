#include "mesh_checks.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <queue>
#include <set>

#include "mesh_error.h"

namespace tb {
namespace {

Eigen::Vector3d row(const Points& V, int i) { return V.row(i).transpose(); }

void check_finite(const std::string& file, const Points& V) {
  Eigen::Index bad = 0;
  for (Eigen::Index i = 0; i < V.rows(); ++i)
    if (!V.row(i).allFinite()) ++bad;
  if (bad) throw MeshError(file, std::to_string(bad) + " vertices have NaN or Inf coordinates");
}

std::string count_of(size_t n, const std::string& what) { return std::to_string(n) + " " + what; }

}  // namespace

double bounding_box_diagonal(const Points& V) {
  if (V.rows() == 0) return 0;
  return (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm();
}

double enclosed_volume(const SurfaceMesh& m) {
  double v = 0;
  for (Eigen::Index t = 0; t < m.F.rows(); ++t)
    v += row(m.V, m.F(t, 0)).dot(row(m.V, m.F(t, 1)).cross(row(m.V, m.F(t, 2)))) / 6.0;
  return v;
}

double total_volume(const TetMesh& m) {
  double v = 0;
  for (Eigen::Index t = 0; t < m.T.rows(); ++t)
    v += tet_volume(row(m.V, m.T(t, 0)), row(m.V, m.T(t, 1)), row(m.V, m.T(t, 2)), row(m.V, m.T(t, 3)));
  return v;
}

double tet_min_dihedral_deg(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                            const Eigen::Vector3d& d) {
  const std::array<Eigen::Vector3d, 4> p{a, b, c, d};
  static const int edges[6][4] = {{0, 1, 2, 3}, {0, 2, 1, 3}, {0, 3, 1, 2}, {1, 2, 0, 3}, {1, 3, 0, 2}, {2, 3, 0, 1}};
  double min_angle = 180;
  for (const auto& e : edges) {
    // Dihedral angle along edge (p0, p1) between faces (p0, p1, p2) and (p0, p1, p3).
    const Eigen::Vector3d& o = p[static_cast<size_t>(e[0])];
    const Eigen::Vector3d axis = (p[static_cast<size_t>(e[1])] - o).normalized();
    const Eigen::Vector3d u = p[static_cast<size_t>(e[2])] - o, w = p[static_cast<size_t>(e[3])] - o;
    const Eigen::Vector3d pu = u - u.dot(axis) * axis, pw = w - w.dot(axis) * axis;
    const double cosang = std::clamp(pu.normalized().dot(pw.normalized()), -1.0, 1.0);
    min_angle = std::min(min_angle, std::acos(cosang) * 180.0 / M_PI);
  }
  return min_angle;
}

double tet_min_dihedral_deg(const TetMesh& m, Eigen::Index t) {
  return tet_min_dihedral_deg(row(m.V, m.T(t, 0)), row(m.V, m.T(t, 1)), row(m.V, m.T(t, 2)), row(m.V, m.T(t, 3)));
}

double min_dihedral_angle_deg(const TetMesh& m) {
  double min_angle = 180;
  for (Eigen::Index t = 0; t < m.T.rows(); ++t) min_angle = std::min(min_angle, tet_min_dihedral_deg(m, t));
  return min_angle;
}

int count_tets_below_dihedral(const TetMesh& m, double degrees) {
  int n = 0;
  for (Eigen::Index t = 0; t < m.T.rows(); ++t) n += tet_min_dihedral_deg(m, t) < degrees;
  return n;
}

SurfaceCheckReport check_and_orient_surface(const std::string& file, SurfaceMesh& m) {
  check_finite(file, m.V);
  const int nv = static_cast<int>(m.V.rows()), nf = static_cast<int>(m.F.rows());
  if (nf == 0) throw MeshError(file, "no triangles");
  size_t bad_index = 0;
  for (int t = 0; t < nf; ++t)
    for (int k = 0; k < 3; ++k)
      if (m.F(t, k) < 0 || m.F(t, k) >= nv) ++bad_index;
  if (bad_index) throw MeshError(file, count_of(bad_index, "triangle vertex indices out of range"));

  // Degenerate: repeated vertex or (relative to the mesh size) zero area.
  const double diag = bounding_box_diagonal(m.V);
  size_t degenerate = 0;
  for (int t = 0; t < nf; ++t) {
    const int a = m.F(t, 0), b = m.F(t, 1), c = m.F(t, 2);
    const double area2 = (row(m.V, b) - row(m.V, a)).cross(row(m.V, c) - row(m.V, a)).norm();
    if (a == b || b == c || a == c || area2 <= 1e-14 * diag * diag) ++degenerate;
  }
  if (degenerate) throw MeshError(file, count_of(degenerate, "degenerate triangles (repeated vertex or zero area)"));

  std::set<std::array<int, 3>> seen;
  size_t duplicates = 0;
  for (int t = 0; t < nf; ++t) {
    std::array<int, 3> key{m.F(t, 0), m.F(t, 1), m.F(t, 2)};
    std::sort(key.begin(), key.end());
    if (!seen.insert(key).second) ++duplicates;
  }
  if (duplicates) throw MeshError(file, count_of(duplicates, "duplicate triangles"));

  // Edge -> incident triangles. Closed and edge-manifold: every edge has exactly 2.
  std::map<std::pair<int, int>, std::vector<int>> edge_faces;
  for (int t = 0; t < nf; ++t)
    for (int k = 0; k < 3; ++k) {
      const int a = m.F(t, k), b = m.F(t, (k + 1) % 3);
      edge_faces[{std::min(a, b), std::max(a, b)}].push_back(t);
    }
  size_t open_edges = 0, nonmanifold_edges = 0;
  for (const auto& [e, faces] : edge_faces) {
    if (faces.size() == 1) ++open_edges;
    if (faces.size() > 2) ++nonmanifold_edges;
  }
  if (nonmanifold_edges)
    throw MeshError(file, "not 2-manifold: " + count_of(nonmanifold_edges, "edges shared by more than two triangles"));
  if (open_edges) throw MeshError(file, "surface not closed: " + count_of(open_edges, "boundary edges"));

  // Vertex-manifold: the triangles around each vertex form one fan (one cycle).
  std::vector<std::vector<int>> vertex_faces(static_cast<size_t>(nv));
  for (int t = 0; t < nf; ++t)
    for (int k = 0; k < 3; ++k) vertex_faces[static_cast<size_t>(m.F(t, k))].push_back(t);
  size_t nonmanifold_vertices = 0, unused = 0;
  for (int v = 0; v < nv; ++v) {
    const auto& fan = vertex_faces[static_cast<size_t>(v)];
    if (fan.empty()) {
      ++unused;
      continue;
    }
    // Walk across edges incident to v, starting at the first triangle.
    std::set<int> reached{fan[0]};
    std::queue<int> q;
    q.push(fan[0]);
    while (!q.empty()) {
      const int t = q.front();
      q.pop();
      for (int k = 0; k < 3; ++k) {
        const int w = m.F(t, k);
        if (w == v) continue;
        for (int u : edge_faces[{std::min(v, w), std::max(v, w)}])
          if (reached.insert(u).second) q.push(u);
      }
    }
    if (reached.size() != fan.size()) ++nonmanifold_vertices;
  }
  if (nonmanifold_vertices)
    throw MeshError(
        file, "not 2-manifold: " + count_of(nonmanifold_vertices, "vertices whose triangles form more than one fan"));
  if (unused) throw MeshError(file, count_of(unused, "vertices used by no triangle"));

  // Consistent orientation: neighbours must traverse their shared edge in opposite
  // directions. Flood-fill each connected component, flipping as needed.
  SurfaceCheckReport report;
  std::vector<int> state(static_cast<size_t>(nf), -1);  // -1 unvisited, 0 keep, 1 flip
  auto directed = [&](int t, int a, int b) {            // does triangle t (with its flip) go a -> b?
    for (int k = 0; k < 3; ++k)
      if (m.F(t, k) == a && m.F(t, (k + 1) % 3) == b) return state[static_cast<size_t>(t)] == 0;
    return state[static_cast<size_t>(t)] == 1;
  };
  size_t nonorientable = 0;
  std::vector<std::vector<int>> components;
  for (int seed = 0; seed < nf; ++seed) {
    if (state[static_cast<size_t>(seed)] != -1) continue;
    components.emplace_back();
    state[static_cast<size_t>(seed)] = 0;
    std::queue<int> q;
    q.push(seed);
    while (!q.empty()) {
      const int t = q.front();
      q.pop();
      components.back().push_back(t);
      for (int k = 0; k < 3; ++k) {
        const int a = m.F(t, k), b = m.F(t, (k + 1) % 3);
        const bool t_goes_ab = directed(t, a, b);
        for (int u : edge_faces[{std::min(a, b), std::max(a, b)}]) {
          if (u == t) continue;
          if (state[static_cast<size_t>(u)] == -1) {
            state[static_cast<size_t>(u)] = 0;
            if (directed(u, a, b) == t_goes_ab) state[static_cast<size_t>(u)] = 1;
            q.push(u);
          } else if (directed(u, a, b) == t_goes_ab) {
            ++nonorientable;
          }
        }
      }
    }
  }
  if (nonorientable)
    throw MeshError(file,
                    "not orientable (a Moebius-like surface): " + count_of(nonorientable / 2, "conflicting edges"));
  for (int t = 0; t < nf; ++t)
    if (state[static_cast<size_t>(t)] == 1) {
      std::swap(m.F(t, 1), m.F(t, 2));
      ++report.flipped_triangles;
    }
  // Outward: each closed component must enclose positive volume.
  for (const auto& comp : components) {
    double vol = 0;
    for (int t : comp) vol += row(m.V, m.F(t, 0)).dot(row(m.V, m.F(t, 1)).cross(row(m.V, m.F(t, 2))));
    if (vol < 0)
      for (int t : comp) {
        std::swap(m.F(t, 1), m.F(t, 2));
        ++report.flipped_triangles;
      }
  }
  return report;
}

int orient_and_check_tets(const std::string& file, TetMesh& m, FlatTets flat_policy) {
  check_finite(file, m.V);
  const int nv = static_cast<int>(m.V.rows());
  size_t bad_index = 0;
  for (Eigen::Index t = 0; t < m.T.rows(); ++t)
    for (int k = 0; k < 4; ++k)
      if (m.T(t, k) < 0 || m.T(t, k) >= nv) ++bad_index;
  if (bad_index) throw MeshError(file, count_of(bad_index, "tetrahedron node indices out of range"));
  const double diag = bounding_box_diagonal(m.V);
  size_t flat = 0;
  int flipped = 0;
  Eigen::Index kept = 0;
  for (Eigen::Index t = 0; t < m.T.rows(); ++t) {
    const double v = tet_volume(row(m.V, m.T(t, 0)), row(m.V, m.T(t, 1)), row(m.V, m.T(t, 2)), row(m.V, m.T(t, 3)));
    if (std::abs(v) <= flat_tet_volume_bound(diag)) {
      ++flat;
      if (flat_policy == FlatTets::Keep) m.T.row(kept++) = m.T.row(t);
      continue;
    }
    if (v < 0) {
      std::swap(m.T(t, 2), m.T(t, 3));
      ++flipped;
    }
    m.T.row(kept++) = m.T.row(t);
  }
  if (flat && flat_policy == FlatTets::Error) throw MeshError(file, count_of(flat, "tetrahedra with zero volume"));
  m.T.conservativeResize(kept, 4);
  return flipped;
}

}  // namespace tb
