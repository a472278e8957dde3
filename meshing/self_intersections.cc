#include "self_intersections.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/repair_self_intersections.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>

#include <string>
#include <vector>

#include "mesh_error.h"

namespace tb {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using CgalMesh = CGAL::Surface_mesh<Kernel::Point_3>;
namespace PMP = CGAL::Polygon_mesh_processing;

CgalMesh to_cgal(const SurfaceMesh& s) {
  CgalMesh m;
  std::vector<CgalMesh::Vertex_index> vs;
  for (Eigen::Index v = 0; v < s.V.rows(); ++v) vs.push_back(m.add_vertex({s.V(v, 0), s.V(v, 1), s.V(v, 2)}));
  for (Eigen::Index t = 0; t < s.F.rows(); ++t) m.add_face(vs[s.F(t, 0)], vs[s.F(t, 1)], vs[s.F(t, 2)]);
  return m;
}

SurfaceMesh from_cgal(const CgalMesh& m) {
  SurfaceMesh s;
  s.V.resize(static_cast<Eigen::Index>(m.number_of_vertices()), 3);
  std::vector<int> index(m.num_vertices(), -1);
  int next = 0;
  for (auto v : m.vertices()) {
    const auto& p = m.point(v);
    s.V.row(next) << p.x(), p.y(), p.z();
    index[v.idx()] = next++;
  }
  s.F.resize(static_cast<Eigen::Index>(m.number_of_faces()), 3);
  int t = 0;
  for (auto f : m.faces()) {
    int k = 0;
    for (auto v : CGAL::vertices_around_face(m.halfedge(f), m)) s.F(t, k++) = index[v.idx()];
    ++t;
  }
  return s;
}

}  // namespace

int count_self_intersections(const SurfaceMesh& surface) {
  const CgalMesh m = to_cgal(surface);
  std::vector<std::pair<CgalMesh::Face_index, CgalMesh::Face_index>> pairs;
  PMP::self_intersections(m.faces(), m, std::back_inserter(pairs));
  return static_cast<int>(pairs.size());
}

SurfaceMesh repair_self_intersections(const SurfaceMesh& surface, const std::string& source) {
  CgalMesh m = to_cgal(surface);
  PMP::experimental::remove_self_intersections(m);
  if (PMP::does_self_intersect(m)) throw MeshError(source, "self-intersections remain after CGAL's repair");
  return from_cgal(m);
}

}  // namespace tb
