#include "hybrid_builder.h"

#include <algorithm>
#include <map>
#include <numeric>

#include "mesh_checks.h"
#include "mesh_error.h"
#include "point_location.h"
#include "vertex_selection.h"
#include "volume_ordering.h"

namespace tb {
namespace {


std::vector<int> surface_to_volume_identity(const SurfaceMesh& s) {
  std::vector<int> map(static_cast<size_t>(s.V.rows()));
  std::iota(map.begin(), map.end(), 0);  // tetrahedralize_surface keeps surface vertices first
  return map;
}

}  // namespace

std::vector<int> boundary_nodes(const TetMesh& m) {
  std::map<std::array<int, 3>, int> face_count;
  static const int faces[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
  for (Eigen::Index t = 0; t < m.T.rows(); ++t)
    for (const auto& f : faces) {
      std::array<int, 3> key{m.T(t, f[0]), m.T(t, f[1]), m.T(t, f[2])};
      std::sort(key.begin(), key.end());
      ++face_count[key];
    }
  std::vector<char> on(static_cast<size_t>(m.V.rows()), 0);
  for (const auto& [f, n] : face_count)
    if (n == 1)
      for (int v : f) on[static_cast<size_t>(v)] = 1;
  std::vector<int> out;
  for (size_t v = 0; v < on.size(); ++v)
    if (on[v]) out.push_back(static_cast<int>(v));
  return out;
}

HybridMesh build_hybrid_from_surface(const SurfaceMesh& surface, const HybridBuildOptions& o,
                                     const std::string& source) {
  HybridMesh h;
  h.fine_surface = surface;
  h.fine_volume =
      o.fine_volume_builder ? o.fine_volume_builder(surface)
                            : tetrahedralize_surface(surface, o.fine_tetgen, source, &h.fine_repair);
  h.fine_surface_to_volume = surface_to_volume_identity(surface);
  const int n_surface = static_cast<int>(surface.V.rows());

  // Selection priority: shape-carrying surface vertices first (corners, creases,
  // then the rest of the surface), interior vertices last, so the coarse mesh
  // keeps the outline and the support face.
  std::vector<int> priority(static_cast<size_t>(h.fine_volume.V.rows()), 3);
  const std::vector<int> surface_priority = surface_feature_priority(surface, o.feature_angle_deg);
  std::copy(surface_priority.begin(), surface_priority.end(), priority.begin());
  for (const Eigen::Vector3d& p : o.include_points) {
    Eigen::Index nearest = 0;
    (surface.V.rowwise() - p.transpose()).rowwise().squaredNorm().minCoeff(&nearest);
    priority[static_cast<size_t>(nearest)] = -1;  // before corners
  }
  const double spacing = o.coarse_spacing > 0 ? o.coarse_spacing
                                              : spacing_for_target_count(h.fine_volume.V, priority,
                                                                         o.target_coarse_nodes, o.selection_seed);
  std::vector<int> selected = select_covering_vertices(h.fine_volume.V, priority, spacing, o.selection_seed);
  if (selected.size() < 4) throw MeshError(source, "too few vertices selected for a coarse mesh (spacing too large)");

  const CoarseMesh coarse =
      build_coarse_mesh(h.fine_volume.V, priority, selected, spacing, surface, o.coarse_quality, source);
  h.coarse_volume = coarse.mesh;
  h.coarse_repair = coarse.repair;

  // Control points: selected vertices on the fine surface, weight 1 on their node.
  std::vector<int> node_tet(static_cast<size_t>(h.coarse_volume.V.rows()), -1), node_slot(node_tet.size(), 0);
  for (Eigen::Index t = h.coarse_volume.T.rows() - 1; t >= 0; --t)  // the first tet holding each node
    for (int k = 0; k < 4; ++k) {
      node_tet[static_cast<size_t>(h.coarse_volume.T(t, k))] = static_cast<int>(t);
      node_slot[static_cast<size_t>(h.coarse_volume.T(t, k))] = k;
    }
  for (size_t n = 0; n < coarse.node_vertex.size(); ++n) {
    if (coarse.node_vertex[n] >= n_surface) continue;
    ControlPoint cp;
    cp.surface_vertex = coarse.node_vertex[n];
    cp.coarse.tet = node_tet[n];
    cp.coarse.weights = Eigen::Vector4d::Unit(node_slot[n]);
    h.control_points.push_back(cp);
  }
  // After the coarse mesh, whose vertex selection follows the fine nodes' order
  // (the paper's meshes stay as they were): the interior nodes and the tets stored
  // along a Z curve, for the parallel sweeps (volume_ordering.h).
  order_along_z_curve(h.fine_volume, n_surface);
  return h;
}

HybridMesh build_hybrid_with_coarse(const SurfaceMesh& surface, const TetMesh& coarse, ControlPointRule rule,
                                    const TetgenOptions* fine_tetgen, const std::string& source) {
  HybridMesh h;
  h.fine_surface = surface;
  h.coarse_volume = coarse;
  if (fine_tetgen) {
    h.fine_volume = tetrahedralize_surface(surface, *fine_tetgen, source, &h.fine_repair);
    h.fine_surface_to_volume = surface_to_volume_identity(surface);
    order_along_z_curve(h.fine_volume, static_cast<int>(surface.V.rows()));  // volume_ordering.h
  }
  std::vector<ControlPoint> embedding(static_cast<size_t>(surface.V.rows()));
  const TetLocator locator(coarse);
  for (Eigen::Index v = 0; v < surface.V.rows(); ++v) {
    const TetEmbedding e = locator.locate(surface.V.row(v).transpose());
    embedding[static_cast<size_t>(v)] = {static_cast<int>(v), e};
  }
  std::vector<int> chosen;
  if (rule == ControlPointRule::AllSurfaceVertices) {
    chosen.resize(embedding.size());
    std::iota(chosen.begin(), chosen.end(), 0);
  } else {
    for (int node : boundary_nodes(coarse)) {
      Eigen::Index nearest = 0;
      (surface.V.rowwise() - coarse.V.row(node)).rowwise().squaredNorm().minCoeff(&nearest);
      chosen.push_back(static_cast<int>(nearest));
    }
    std::sort(chosen.begin(), chosen.end());
    chosen.erase(std::unique(chosen.begin(), chosen.end()), chosen.end());
  }
  for (int v : chosen) h.control_points.push_back(embedding[static_cast<size_t>(v)]);
  return h;
}

double max_embedding_distance(const HybridMesh& h) {
  double worst = 0;
  const TetLocator locator(h.coarse_volume);
  for (Eigen::Index v = 0; v < h.fine_surface.V.rows(); ++v)
    worst = std::max(worst, locator.locate(h.fine_surface.V.row(v).transpose()).distance);
  return worst;
}

}  // namespace tb
