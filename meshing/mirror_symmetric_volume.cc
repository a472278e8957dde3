#include "mirror_symmetric_volume.h"

#include <array>
#include <cmath>
#include <map>

#include "mesh_checks.h"
#include "mesh_error.h"

namespace tb {
namespace {

/// Positions on a 1e-12 m lattice: the same point computed two ways (a surface
/// vertex and its reflected quarter copy) gets one key.
using PointKey = std::array<long long, 3>;
PointKey key_of(double x, double y, double z) {
  return {std::llround(x * 1e12), std::llround(y * 1e12), std::llround(z * 1e12)};
}

/// Vertices deduplicated by position, in insertion order.
struct VertexSet {
  std::map<PointKey, int> index;
  std::vector<Eigen::RowVector3d> points;
  int add(const Eigen::RowVector3d& p) {
    auto [it, inserted] = index.emplace(key_of(p(0), p(1), p(2)), static_cast<int>(points.size()));
    if (inserted) points.push_back(p);
    return it->second;
  }
};

/// The closed quarter x >= 0, y >= 0: the surface's triangles there plus a grid on
/// each cut plane with the surface's spacing (the planes' boundary points are
/// surface vertices, so the quarter's surface is watertight).
SurfaceMesh quarter_surface(const SurfaceMesh& surface, const CubeSpec& spec, const std::string& source) {
  VertexSet vertices;
  std::vector<std::array<int, 3>> triangles;
  for (Eigen::Index t = 0; t < surface.F.rows(); ++t) {
    Eigen::RowVector3d lo = surface.V.row(surface.F(t, 0)), hi = lo;
    for (int k = 1; k < 3; ++k) {
      lo = lo.cwiseMin(surface.V.row(surface.F(t, k)));
      hi = hi.cwiseMax(surface.V.row(surface.F(t, k)));
    }
    if ((lo(0) < 0 && hi(0) > 0) || (lo(1) < 0 && hi(1) > 0))
      throw MeshError(source, "triangle " + std::to_string(t) +
                                  " crosses the plane x = 0 or y = 0: no mirror-symmetric volume mesh");
    if (lo(0) < 0 || lo(1) < 0) continue;  // another quarter's
    std::array<int, 3> tri{};
    for (int k = 0; k < 3; ++k) tri[static_cast<size_t>(k)] = vertices.add(surface.V.row(surface.F(t, k)));
    triangles.push_back(tri);
  }
  // Grids on x = 0 (lattice columns j along y) and y = 0 (columns i along x), with
  // the generator's coordinates so that boundary points coincide.
  for (int plane = 0; plane < 2; ++plane) {
    const int n = plane == 0 ? spec.ny : spec.nx;
    auto point = [&](int a, int k) {
      const double along = centred_grid_coordinate(spec.side, n, n / 2 + a);
      const double z = spec.height * static_cast<double>(k) / spec.nz;
      return vertices.add(plane == 0 ? Eigen::RowVector3d(0, along, z) : Eigen::RowVector3d(along, 0, z));
    };
    for (int a = 0; a < n / 2; ++a)
      for (int k = 0; k < spec.nz; ++k) {
        const int p00 = point(a, k), p10 = point(a + 1, k), p11 = point(a + 1, k + 1), p01 = point(a, k + 1);
        triangles.push_back({p00, p10, p11});
        triangles.push_back({p00, p11, p01});
      }
  }
  SurfaceMesh q;
  q.V.resize(static_cast<Eigen::Index>(vertices.points.size()), 3);
  for (size_t v = 0; v < vertices.points.size(); ++v) q.V.row(static_cast<Eigen::Index>(v)) = vertices.points[v];
  q.F.resize(static_cast<Eigen::Index>(triangles.size()), 3);
  for (size_t t = 0; t < triangles.size(); ++t)
    q.F.row(static_cast<Eigen::Index>(t)) << triangles[t][0], triangles[t][1], triangles[t][2];
  check_and_orient_surface(source + " (quarter)", q);  // closed, manifold, outward
  return q;
}

}  // namespace

TetMesh tetrahedralize_symmetric_cube(const SurfaceMesh& surface, const CubeSpec& spec, const TetgenOptions& options,
                                      const std::string& source) {
  if (spec.nx % 2 != 0 || spec.ny % 2 != 0)
    throw MeshError(source, "a mirror-symmetric volume mesh needs even nx and ny (x = 0 and y = 0 on the grid)");
  const TetMesh quarter =
      tetrahedralize_surface(quarter_surface(surface, spec, source), options, source + " (quarter)");

  // The surface's vertices first, in order; then the quarters' other vertices.
  VertexSet vertices;
  for (Eigen::Index v = 0; v < surface.V.rows(); ++v)
    if (vertices.add(surface.V.row(v)) != v) throw MeshError(source, "duplicate surface vertex " + std::to_string(v));
  std::vector<char> surface_covered(static_cast<size_t>(surface.V.rows()), 0);
  std::vector<std::array<int, 4>> tets;
  const int signs[4][2] = {{1, 1}, {-1, 1}, {1, -1}, {-1, -1}};
  std::vector<int> image(static_cast<size_t>(quarter.V.rows()));
  for (const auto& s : signs) {
    for (Eigen::Index v = 0; v < quarter.V.rows(); ++v) {
      Eigen::RowVector3d p = quarter.V.row(v);
      p(0) *= s[0];
      p(1) *= s[1];
      const int i = vertices.add(p);
      image[static_cast<size_t>(v)] = i;
      if (i < surface.V.rows()) surface_covered[static_cast<size_t>(i)] = 1;
    }
    const bool reflected = s[0] * s[1] < 0;  // one reflection reverses orientation
    for (Eigen::Index t = 0; t < quarter.T.rows(); ++t) {
      std::array<int, 4> tet{};
      for (int k = 0; k < 4; ++k) tet[static_cast<size_t>(k)] = image[static_cast<size_t>(quarter.T(t, k))];
      if (reflected) std::swap(tet[1], tet[2]);
      tets.push_back(tet);
    }
  }
  for (size_t v = 0; v < surface_covered.size(); ++v)
    if (!surface_covered[v])
      throw MeshError(source, "surface vertex " + std::to_string(v) +
                                  " is not the mirror image of a quarter vertex: the surface is not mirror-symmetric");
  TetMesh m;
  m.V.resize(static_cast<Eigen::Index>(vertices.points.size()), 3);
  for (size_t v = 0; v < vertices.points.size(); ++v) m.V.row(static_cast<Eigen::Index>(v)) = vertices.points[v];
  m.T.resize(static_cast<Eigen::Index>(tets.size()), 4);
  for (size_t t = 0; t < tets.size(); ++t)
    m.T.row(static_cast<Eigen::Index>(t)) << tets[t][0], tets[t][1], tets[t][2], tets[t][3];
  orient_and_check_tets(source, m, FlatTets::Error);
  return m;
}

}  // namespace tb
