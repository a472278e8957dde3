#include "vertex_selection.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <numeric>
#include <unordered_map>

#include "mesh_checks.h"

namespace tb {

std::vector<int> surface_feature_priority(const SurfaceMesh& s, double feature_angle_deg) {
  const double cos_limit = std::cos(feature_angle_deg * M_PI / 180.0);
  std::vector<Eigen::Vector3d> normals(static_cast<size_t>(s.F.rows()));
  for (Eigen::Index t = 0; t < s.F.rows(); ++t) {
    const Eigen::Vector3d a = s.V.row(s.F(t, 0)), b = s.V.row(s.F(t, 1)), c = s.V.row(s.F(t, 2));
    normals[static_cast<size_t>(t)] = (b - a).cross(c - a).normalized();
  }
  std::map<std::pair<int, int>, std::vector<int>> edge_faces;
  for (Eigen::Index t = 0; t < s.F.rows(); ++t)
    for (int k = 0; k < 3; ++k) {
      const int a = s.F(t, k), b = s.F(t, (k + 1) % 3);
      edge_faces[{std::min(a, b), std::max(a, b)}].push_back(static_cast<int>(t));
    }
  std::vector<int> feature_edges(static_cast<size_t>(s.V.rows()), 0);
  for (const auto& [e, f] : edge_faces)
    if (f.size() == 2 && normals[static_cast<size_t>(f[0])].dot(normals[static_cast<size_t>(f[1])]) < cos_limit) {
      ++feature_edges[static_cast<size_t>(e.first)];
      ++feature_edges[static_cast<size_t>(e.second)];
    }
  std::vector<int> priority(feature_edges.size());
  for (size_t v = 0; v < priority.size(); ++v) priority[v] = feature_edges[v] >= 3 ? 0 : feature_edges[v] >= 1 ? 1 : 2;
  return priority;
}

std::vector<int> seed_rank(int n, unsigned seed) {
  std::vector<int> rank(static_cast<size_t>(n));
  std::iota(rank.begin(), rank.end(), 0);
  if (seed == 0) return rank;
  uint64_t state = seed;
  auto next = [&state] {  // splitmix64
    uint64_t z = (state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  };
  for (int i = n - 1; i > 0; --i) std::swap(rank[static_cast<size_t>(i)], rank[next() % static_cast<uint64_t>(i + 1)]);
  return rank;
}

std::vector<int> select_covering_vertices(const Points& V, const std::vector<int>& priority, double spacing,
                                          unsigned seed) {
  const std::vector<int> rank = seed_rank(static_cast<int>(V.rows()), seed);
  std::vector<int> order(static_cast<size_t>(V.rows()));
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    const auto ua = static_cast<size_t>(a), ub = static_cast<size_t>(b);
    return priority[ua] != priority[ub] ? priority[ua] < priority[ub] : rank[ua] < rank[ub];
  });
  std::vector<int> selected;
  if (V.rows() == 0) return selected;
  const double s2 = spacing * spacing;
  // Selected vertices bucketed in a grid of cells a little wider than `spacing`:
  // a vertex closer than `spacing` to v lies in v's cell or a neighbour (the
  // margin absorbs the rounding of the cell coordinates), so only 27 cells are
  // searched. The same selection as comparing with every selected vertex.
  const double cell = spacing * (1 + 1e-9);
  const Eigen::RowVector3d origin = V.colwise().minCoeff();
  const Eigen::RowVector3d extent = V.colwise().maxCoeff() - origin;
  const double max_cells = 1 << 20;  // per axis; beyond, cells grow (still correct, fewer buckets)
  const double size = std::max(cell, extent.maxCoeff() / max_cells);
  auto coordinate = [&](double x, int axis) { return static_cast<int64_t>(std::floor((x - origin(axis)) / size)); };
  auto key = [](int64_t i, int64_t j, int64_t k) { return (i * 2097152 + j) * 2097152 + k; };  // 2^21 per axis
  std::unordered_map<int64_t, std::vector<int>> cells;
  for (int v : order) {
    const int64_t ci = coordinate(V(v, 0), 0), cj = coordinate(V(v, 1), 1), ck = coordinate(V(v, 2), 2);
    bool covered = false;
    for (int64_t i = ci - 1; i <= ci + 1 && !covered; ++i)
      for (int64_t j = cj - 1; j <= cj + 1 && !covered; ++j)
        for (int64_t k = ck - 1; k <= ck + 1 && !covered; ++k) {
          const auto it = cells.find(key(i, j, k));
          if (it == cells.end()) continue;
          for (int w : it->second)
            if ((V.row(v) - V.row(w)).squaredNorm() < s2) {
              covered = true;
              break;
            }
        }
    if (!covered) {
      selected.push_back(v);
      cells[key(ci, cj, ck)].push_back(v);
    }
  }
  return selected;
}

double spacing_for_target_count(const Points& V, const std::vector<int>& priority, int target_count, unsigned seed) {
  double lo = 0, hi = bounding_box_diagonal(V);
  double best = hi;
  int best_miss = std::numeric_limits<int>::max();
  for (int it = 0; it < 50; ++it) {
    const double mid = 0.5 * (lo + hi);
    const int count = static_cast<int>(select_covering_vertices(V, priority, mid, seed).size());
    if (std::abs(count - target_count) < best_miss) {
      best_miss = std::abs(count - target_count);
      best = mid;
    }
    if (count == target_count) break;
    (count > target_count ? lo : hi) = mid;
  }
  return best;
}

}  // namespace tb
