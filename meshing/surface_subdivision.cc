#include "surface_subdivision.h"

#include <stdexcept>
#include <unordered_map>
#include <vector>

namespace tb {
namespace {

/// One level of the 1-to-4 split.
SurfaceMesh split_once(const SurfaceMesh& s) {
  const Eigen::Index n = s.V.rows();
  std::unordered_map<long long, int> midpoint;  // edge (min, max) -> new vertex
  midpoint.reserve(static_cast<size_t>(3 * s.F.rows() / 2));
  std::vector<Eigen::RowVector3d> added;
  auto mid = [&](int a, int b) {
    const long long key = static_cast<long long>(std::min(a, b)) * n + std::max(a, b);
    auto [it, inserted] = midpoint.emplace(key, static_cast<int>(n + static_cast<Eigen::Index>(added.size())));
    if (inserted) added.push_back(0.5 * (s.V.row(a) + s.V.row(b)));
    return it->second;
  };
  SurfaceMesh out;
  out.F.resize(4 * s.F.rows(), 3);
  for (Eigen::Index t = 0; t < s.F.rows(); ++t) {
    const int a = s.F(t, 0), b = s.F(t, 1), c = s.F(t, 2);
    const int ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
    out.F.row(4 * t) << a, ab, ca;
    out.F.row(4 * t + 1) << ab, b, bc;
    out.F.row(4 * t + 2) << ca, bc, c;
    out.F.row(4 * t + 3) << ab, bc, ca;
  }
  out.V.resize(n + static_cast<Eigen::Index>(added.size()), 3);
  out.V.topRows(n) = s.V;
  for (size_t k = 0; k < added.size(); ++k) out.V.row(n + static_cast<Eigen::Index>(k)) = added[k];
  return out;
}

}  // namespace

SurfaceMesh subdivide_surface(const SurfaceMesh& surface, int levels) {
  if (levels < 0)
    throw std::invalid_argument("surface subdivision: levels must be >= 0, got " + std::to_string(levels));
  SurfaceMesh s = surface;
  for (int l = 0; l < levels; ++l) s = split_once(s);
  return s;
}

}  // namespace tb
