#include "mesh_recipe.h"

#include <filesystem>
#include <iomanip>
#include <sstream>

#include "atomic_file.h"
#include "mesh_checks.h"
#include "mesh_error.h"
#include "mesh_io.h"
#include "self_intersections.h"
#include "strict_json.h"

namespace tb {

namespace fs = std::filesystem;

MeshRecipe parse_mesh_recipe(const nlohmann::json& j, const std::string& base_dir, const std::string& where) {
  StrictObject o(j, where);
  MeshRecipe r;
  const std::string type = o.text("type", std::nullopt, {"cube", "files"});
  auto path = [&](const std::string& p) { return fs::path(p).is_absolute() ? p : (fs::path(base_dir) / p).lexically_normal().string(); };
  if (type == "cube") {
    r.kind = MeshRecipe::Kind::Cube;
    r.cube.side = o.number("side", 0.1, 1e-9, 1e9);
    r.cube.height = o.number("height", 0.1, 1e-9, 1e9);
    r.cube.nx = o.integer("nx", 10, 1, 1000);
    r.cube.ny = o.integer("ny", 10, 1, 1000);
    r.cube.nz = o.integer("nz", 12, 1, 1000);
  } else {
    r.kind = MeshRecipe::Kind::Files;
    r.surface_file = path(o.text("surface", std::nullopt));
    if (o.has("coarse")) r.coarse_file = path(o.text("coarse", std::nullopt));
    r.unit_scale = o.number("unit_scale", 1.0, 1e-12, 1e12);
    r.repair_self_intersections = o.boolean("repair_self_intersections", false);
    r.control_points = o.text("control_points", "nearest_to_coarse_surface_nodes",
                              {"nearest_to_coarse_surface_nodes", "all_surface_vertices"}) == "all_surface_vertices"
                           ? ControlPointRule::AllSurfaceVertices
                           : ControlPointRule::NearestToCoarseSurfaceNodes;
    r.build_fine_volume = o.boolean("build_fine_volume", true);
  }
  StrictObject fine = o.object("fine_tetgen", true);
  r.build.fine_tetgen.radius_edge_ratio = fine.number("radius_edge_ratio", 1.414, 0, 100);
  r.build.fine_tetgen.max_volume = fine.number("max_volume", 0, 0, 1e9);
  fine.finish();
  StrictObject coarse = o.object("coarse_selection", true);
  r.build.target_coarse_nodes = coarse.integer("target_nodes", 150, 4, 10000000);
  r.build.coarse_spacing = coarse.number("spacing", 0, 0, 1e9);
  r.build.feature_angle_deg = coarse.number("feature_angle_deg", 30, 0, 180);
  coarse.finish();
  o.finish();
  return r;
}

HybridMesh build_mesh(const MeshRecipe& r, MeshReport& report) {
  if (r.kind == MeshRecipe::Kind::Cube) {
    SurfaceMesh s = make_cube_surface(r.cube);
    report.flipped_triangles = check_and_orient_surface("cube", s).flipped_triangles;
    return build_hybrid_from_surface(s, r.build, "cube");
  }
  SurfaceMesh s = read_surface(r.surface_file, r.unit_scale);
  report.flipped_triangles = check_and_orient_surface(r.surface_file, s).flipped_triangles;
  report.self_intersections_found = count_self_intersections(s);
  if (report.self_intersections_found) {
    if (!r.repair_self_intersections)
      throw MeshError(r.surface_file, std::to_string(report.self_intersections_found) +
                                          " pairs of self-intersecting triangles (set repair_self_intersections / "
                                          "--repair-self-intersections to repair them with CGAL)");
    report.vertices_before_repair = static_cast<int>(s.V.rows());
    s = repair_self_intersections(s, r.surface_file);
    report.repaired = true;
    check_and_orient_surface(r.surface_file, s);
  }
  if (r.coarse_file.empty()) return build_hybrid_from_surface(s, r.build, r.surface_file);
  const TetMesh coarse = read_volume(r.coarse_file, r.unit_scale);
  return build_hybrid_with_coarse(s, coarse, r.control_points, r.build_fine_volume ? &r.build.fine_tetgen : nullptr,
                                  r.surface_file);
}

nlohmann::json MeshReport::to_json(const HybridMesh& h) const {
  nlohmann::json j;
  j["surface_vertices"] = h.fine_surface.V.rows();
  j["surface_triangles"] = h.fine_surface.F.rows();
  j["fine_nodes"] = h.fine_volume.V.rows();
  j["fine_tets"] = h.fine_volume.T.rows();
  j["coarse_nodes"] = h.coarse_volume.V.rows();
  j["coarse_tets"] = h.coarse_volume.T.rows();
  j["control_points"] = h.control_points.size();
  j["surface_enclosed_volume"] = enclosed_volume(h.fine_surface);
  j["fine_volume"] = h.fine_volume.T.rows() ? total_volume(h.fine_volume) : 0.0;
  j["coarse_volume"] = total_volume(h.coarse_volume);
  j["min_dihedral_deg"] = h.fine_volume.T.rows() ? min_dihedral_angle_deg(h.fine_volume) : 0.0;
  j["coarse_min_dihedral_deg"] = min_dihedral_angle_deg(h.coarse_volume);
  j["max_embedding_distance"] = max_embedding_distance(h);
  j["self_intersections_found"] = self_intersections_found;
  j["self_intersections_repaired"] = repaired;
  if (repaired) j["surface_vertices_before_repair"] = vertices_before_repair;
  j["triangles_reoriented"] = flipped_triangles;
  return j;
}

void write_mesh_folder(const std::string& dir, const HybridMesh& h, const MeshReport& report) {
  fs::create_directories(dir);
  const fs::path d(dir);
  write_surface_vtu((d / "fine_surface.vtu").string(), h.fine_surface);
  write_obj((d / "fine_surface.obj").string(), h.fine_surface);
  if (h.fine_volume.T.rows()) write_volume_vtu((d / "fine_volume.vtu").string(), h.fine_volume);
  write_volume_vtu((d / "coarse_volume.vtu").string(), h.coarse_volume);
  Points cp(static_cast<Eigen::Index>(h.control_points.size()), 3);
  Eigen::MatrixXd ids(cp.rows(), 1);
  std::ostringstream csv;
  csv << std::setprecision(17) << "surface_vertex,coarse_tet,w0,w1,w2,w3\n";
  for (size_t k = 0; k < h.control_points.size(); ++k) {
    const auto& c = h.control_points[k];
    cp.row(static_cast<Eigen::Index>(k)) = h.fine_surface.V.row(c.surface_vertex);
    ids(static_cast<Eigen::Index>(k), 0) = c.surface_vertex;
    csv << c.surface_vertex << ',' << c.coarse_tet << ',' << c.weights(0) << ',' << c.weights(1) << ','
        << c.weights(2) << ',' << c.weights(3) << '\n';
  }
  write_points_vtu((d / "control_points.vtu").string(), cp, {{"surface_vertex", ids}});
  write_file_atomically((d / "control_points.csv").string(), csv.str());
  write_file_atomically((d / "summary.json").string(), report.to_json(h).dump(2) + "\n");
}

}  // namespace tb
