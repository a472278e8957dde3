#include "mesh_recipe.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "atomic_file.h"
#include "mesh_checks.h"
#include "mesh_error.h"
#include "mesh_io.h"
#include "mirror_symmetric_volume.h"
#include "self_intersections.h"
#include "staged_folder.h"
#include "strict_json.h"
#include "surface_subdivision.h"
#include "tetgen_driver.h"
#include "text_parsing.h"

namespace tb {

namespace fs = std::filesystem;

namespace {
const char* control_point_rule_name(ControlPointRule rule) {
  return rule == ControlPointRule::AllSurfaceVertices ? "all_surface_vertices" : "nearest_to_coarse_surface_nodes";
}
}  // namespace

nlohmann::json MeshRecipe::to_json() const {
  nlohmann::json j;
  if (kind == Kind::Cube) {
    j["type"] = "cube";
    j["side"] = cube.side;
    j["height"] = cube.height;
    j["nx"] = cube.nx;
    j["ny"] = cube.ny;
    j["nz"] = cube.nz;
    j["symmetric_fine_volume"] = symmetric_fine_volume;
  } else if (kind == Kind::Shape) {
    j["type"] = "shape";
    j["shape"] = shape.name;
    j["resolution"] = shape.resolution;
  } else {
    j["type"] = "files";
    j["surface"] = surface_reference.empty() ? surface_file : surface_reference;
    if (!coarse_file.empty()) j["coarse"] = coarse_reference.empty() ? coarse_file : coarse_reference;
    j["unit_scale"] = unit_scale;
    j["repair_self_intersections"] = repair_self_intersections;
    j["control_points"] = control_point_rule_name(control_points);
    j["build_fine_volume"] = build_fine_volume;
  }
  j["refine_levels"] = refine_levels;
  j["fine_tetgen"] = {{"radius_edge_ratio", build.fine_tetgen.radius_edge_ratio},
                      {"max_volume", build.fine_tetgen.max_volume}};
  j["coarse_selection"] = {{"target_nodes", build.target_coarse_nodes},
                           {"spacing", build.coarse_spacing},
                           {"feature_angle_deg", build.feature_angle_deg},
                           {"min_dihedral_deg", build.coarse_quality.min_dihedral_deg},
                           {"seed", build.selection_seed}};
  if (!build.include_points.empty()) {
    j["coarse_selection"]["include_points"] = nlohmann::json::array();
    for (const auto& p : build.include_points) j["coarse_selection"]["include_points"].push_back({p.x(), p.y(), p.z()});
  }
  return j;
}

MeshRecipe parse_mesh_recipe(const nlohmann::json& j, const std::string& base_dir, const std::string& where,
                             const DataDir& data) {
  StrictObject o(j, where);
  return parse_mesh_recipe(o.in_schema("scenario.mesh"), base_dir, data);
}

MeshRecipe parse_mesh_recipe(StrictObject o, const std::string& base_dir, const DataDir& data) {
  MeshRecipe r;
  const std::string type = o.text("type", std::nullopt, {"cube", "files", "shape"});
  // A file: a data reference (read from the data directory, recorded as written)
  // or a path relative to the scenario file that states it.
  auto file = [&](const std::string& key, std::string& reference) {
    const std::string p = o.text(key, std::nullopt);
    if (is_data_reference(p)) {
      reference = p;
      return resolve_data_file(p, data, o.where() + "." + key);
    }
    if (fs::path(p).is_absolute()) return p;
    return (fs::path(o.directory_of(key, base_dir)) / p).lexically_normal().string();
  };
  // Every fallback is the default of the field it fills (declared once, in the
  // structs of mesh_recipe.h, cube_generator.h, tetgen_driver.h, hybrid_builder.h).
  if (type == "cube") {
    r.kind = MeshRecipe::Kind::Cube;
    r.cube.side = o.number("side", r.cube.side, 1e-9, 1e9);
    r.cube.height = o.number("height", r.cube.height, 1e-9, 1e9);
    r.cube.nx = o.integer("nx", r.cube.nx, 1, 1000);
    r.cube.ny = o.integer("ny", r.cube.ny, 1, 1000);
    r.cube.nz = o.integer("nz", r.cube.nz, 1, 1000);
    r.symmetric_fine_volume = o.boolean("symmetric_fine_volume", r.symmetric_fine_volume);
  } else if (type == "shape") {
    r.kind = MeshRecipe::Kind::Shape;
    r.shape.name = o.text("shape", std::nullopt, shape_names());
    r.shape.resolution = o.integer("resolution", r.shape.resolution, kMinShapeResolution, kMaxShapeResolution);
  } else {
    r.kind = MeshRecipe::Kind::Files;
    r.surface_file = file("surface", r.surface_reference);
    if (o.has("coarse")) r.coarse_file = file("coarse", r.coarse_reference);
    r.unit_scale = o.number("unit_scale", r.unit_scale, 1e-12, 1e12);
    r.repair_self_intersections = o.boolean("repair_self_intersections", r.repair_self_intersections);
    r.control_points = o.text("control_points", control_point_rule_name(r.control_points),
                              {"nearest_to_coarse_surface_nodes", "all_surface_vertices"}) == "all_surface_vertices"
                           ? ControlPointRule::AllSurfaceVertices
                           : ControlPointRule::NearestToCoarseSurfaceNodes;
    r.build_fine_volume = o.boolean("build_fine_volume", r.build_fine_volume);
  }
  r.refine_levels = o.integer("refine_levels", r.refine_levels, 0, 6);
  if (r.refine_levels > 0 && r.symmetric_fine_volume)
    o.fail("refine_levels", "is not supported with symmetric_fine_volume (its cut-plane grids follow nx, ny, nz)");
  StrictObject fine = o.object("fine_tetgen", true);
  r.build.fine_tetgen.radius_edge_ratio =
      fine.number("radius_edge_ratio", r.build.fine_tetgen.radius_edge_ratio, 0, 100);
  // The cube's default bound is the paper's (kPaperCubeFineMaxVolume); other surfaces have none.
  r.build.fine_tetgen.max_volume =
      fine.number("max_volume",
                  r.kind == MeshRecipe::Kind::Cube ? kPaperCubeFineMaxVolume : r.build.fine_tetgen.max_volume, 0, 1e9);
  fine.finish();
  StrictObject coarse = o.object("coarse_selection", true);
  r.build.target_coarse_nodes = coarse.integer("target_nodes", r.build.target_coarse_nodes, 4, 10000000);
  r.build.coarse_spacing = coarse.number("spacing", r.build.coarse_spacing, 0, 1e9);
  r.build.feature_angle_deg = coarse.number("feature_angle_deg", r.build.feature_angle_deg, 0, 180);
  r.build.coarse_quality.min_dihedral_deg =
      coarse.number("min_dihedral_deg", r.build.coarse_quality.min_dihedral_deg, 0, 30);
  r.build.selection_seed =
      static_cast<unsigned>(coarse.integer("seed", static_cast<int>(r.build.selection_seed), 0, 1000000000));
  if (coarse.has("include_points")) {
    const nlohmann::json& points = coarse.raw("include_points");
    if (!points.is_array()) coarse.fail("include_points", "must be an array of [x, y, z] points");
    for (const auto& p : points) {
      if (!p.is_array() || p.size() != 3 || !p[0].is_number() || !p[1].is_number() || !p[2].is_number())
        coarse.fail("include_points", "must be an array of [x, y, z] points");
      r.build.include_points.emplace_back(p[0].get<double>(), p[1].get<double>(), p[2].get<double>());
    }
  }
  coarse.finish();
  o.finish();
  return r;
}

namespace {

void print_warnings(const MeshReport& report) {
  for (const auto& w : report.warnings) std::cerr << "tissuebench: warning: " << w << "\n";
}

/// Tissue is centimetres to decimetres across: a surface far outside [1 mm, 10 m]
/// was most likely read in the wrong unit.
void check_unit_scale(const SurfaceMesh& s, const std::string& source, double unit_scale, MeshReport& report) {
  constexpr double kSmallest = 1e-3, kLargest = 10;  // m, bounding-box diagonal
  const double diagonal = bounding_box_diagonal(s.V);
  if (diagonal >= kSmallest && diagonal <= kLargest) return;
  std::ostringstream w;
  w << source << ": bounding-box diagonal " << diagonal << " m after unit_scale " << unit_scale
    << " is outside [1 mm, 10 m]: is unit_scale right (0.01 for centimetres, 0.001 for millimetres)?";
  report.warnings.push_back(w.str());
  std::cerr << "tissuebench: warning: " << w.str() << "\n";
}

/// The recipe's refinement: the surface split refine_levels times, the fine volume
/// bound scaled by 8^-refine_levels (every tet split in eight, roughly).
HybridBuildOptions refine(const MeshRecipe& r, SurfaceMesh& s) {
  s = subdivide_surface(s, r.refine_levels);
  HybridBuildOptions build = r.build;
  build.fine_tetgen.max_volume *= std::ldexp(1.0, -3 * r.refine_levels);
  return build;
}
}  // namespace

HybridMesh build_mesh(const MeshRecipe& r, MeshReport& report) {
  report.warnings.clear();
  if (r.kind == MeshRecipe::Kind::Cube) {
    SurfaceMesh s = make_cube_surface(r.cube);
    report.flipped_triangles = check_and_orient_surface("cube", s).flipped_triangles;
    check_unit_scale(s, "cube", 1.0, report);
    HybridBuildOptions build = refine(r, s);
    if (r.symmetric_fine_volume)
      build.fine_volume_builder = [&r](const SurfaceMesh& surface) {
        return tetrahedralize_symmetric_cube(surface, r.cube, r.build.fine_tetgen, "cube");
      };
    return build_hybrid_from_surface(s, build, "cube");
  }
  if (r.kind == MeshRecipe::Kind::Shape) {
    const std::string source = "shape " + r.shape.name;
    SurfaceMesh s = make_shape_surface(r.shape);
    report.flipped_triangles = check_and_orient_surface(source, s).flipped_triangles;
    check_unit_scale(s, source, 1.0, report);
    if (const int n = count_self_intersections(s))
      throw MeshError(source, std::to_string(n) + " pairs of self-intersecting triangles (a generator bug)");
    return build_hybrid_from_surface(s, refine(r, s), source);
  }
  SurfaceMesh s = read_surface(r.surface_file, r.unit_scale);
  report.flipped_triangles = check_and_orient_surface(r.surface_file, s).flipped_triangles;
  check_unit_scale(s, r.surface_file, r.unit_scale, report);
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
  const HybridBuildOptions build = refine(r, s);
  if (r.coarse_file.empty()) return build_hybrid_from_surface(s, build, r.surface_file);
  const TetMesh coarse = read_volume(r.coarse_file, r.unit_scale);
  return build_hybrid_with_coarse(s, coarse, r.control_points, r.build_fine_volume ? &build.fine_tetgen : nullptr,
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
  j["fine_tets_below_5deg"] = count_tets_below_dihedral(h.fine_volume, 5);
  j["coarse_tets_below_5deg"] = count_tets_below_dihedral(h.coarse_volume, 5);
  j["coarse_repair"] = {{"boundary_slivers_removed", h.coarse_repair.boundary_slivers_removed},
                        {"vertices_moved", h.coarse_repair.vertices_moved},
                        {"interior_vertices_dropped", h.coarse_repair.interior_vertices_dropped},
                        {"remeshes", h.coarse_repair.remeshes},
                        {"slivers_left", h.coarse_repair.slivers_left}};
  j["fine_repair"] = {{"interior_points_merged", h.fine_repair.merged},
                      {"interior_points_not_merged", h.fine_repair.refused},
                      {"flat_tet_points_collapsed", h.fine_repair.flat_tets_collapsed}};
  j["max_embedding_distance"] = max_embedding_distance(h);
  j["self_intersections_found"] = self_intersections_found;
  j["self_intersections_repaired"] = repaired;
  if (repaired) j["surface_vertices_before_repair"] = vertices_before_repair;
  j["triangles_reoriented"] = flipped_triangles;
  j["warnings"] = warnings;
  return j;
}

namespace {

/// The files of a mesh folder, summary.json last.
const char* const kMeshFolderFiles[] = {"fine_surface.vtu", "fine_surface.obj",    "fine_volume.vtu",
                                        "coarse_volume.vtu", "control_points.vtu", "control_points.csv",
                                        "summary.json"};

void write_mesh_files(const fs::path& d, const HybridMesh& h, const MeshReport& report) {
  fs::create_directories(d);
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
    csv << c.surface_vertex << ',' << c.coarse.tet << ',' << c.coarse.weights(0) << ',' << c.coarse.weights(1) << ',' << c.coarse.weights(2)
        << ',' << c.coarse.weights(3) << '\n';
  }
  write_points_vtu((d / "control_points.vtu").string(), cp, {{"surface_vertex", ids}});
  write_file_atomically((d / "control_points.csv").string(), csv.str());
  write_file_atomically((d / "summary.json").string(), report.to_json(h).dump(2) + "\n");
}

}  // namespace

void write_mesh_folder(const std::string& dir, const HybridMesh& h, const MeshReport& report) {
  // Staged, then renamed into place (staged_folder.h): an interrupted run leaves the
  // previous folder or the whole new one. A folder that holds files of its own
  // (`tissuebench mesh --out` into a folder of the user's) is not replaced: the new
  // files are moved into it one by one, each whole, summary.json last.
  const fs::path d = fs::path(dir).lexically_normal();
  const fs::path target = d.has_filename() ? d : d.parent_path();
  remove_stale_staging(target);
  const fs::path staging = staging_folder(target);
  std::error_code ec;
  fs::remove_all(staging, ec);
  try {
    write_mesh_files(staging, h, report);
    bool own_files = false;
    if (fs::is_directory(target))
      for (const auto& entry : fs::directory_iterator(target)) {
        const std::string name = entry.path().filename().string();
        own_files |= std::find(std::begin(kMeshFolderFiles), std::end(kMeshFolderFiles), name) ==
                     std::end(kMeshFolderFiles);
      }
    if (!own_files) {
      replace_folder(staging, target);
      return;
    }
    for (const char* name : kMeshFolderFiles)
      if (fs::exists(staging / name)) fs::rename(staging / name, target / name);
    fs::remove_all(staging);
  } catch (...) {
    fs::remove_all(staging, ec);
    throw;
  }
}

}  // namespace tb

namespace tb {

namespace {

/// FNV-1a, 64 bits: fast, stable across runs and machines.
uint64_t fnv1a(const std::string& bytes, uint64_t h = 1469598103934665603ull) {
  for (unsigned char c : bytes) h = (h ^ c) * 1099511628211ull;
  return h;
}

/// Cache format version: bump when the mesh pipeline or the folder layout changes.
constexpr const char* kCacheFormat = "tissuebench-mesh-cache-7";

HybridMesh read_mesh_folder(const std::string& dir, MeshReport& report) {
  const fs::path d(dir);
  HybridMesh h;
  h.fine_surface = read_surface((d / "fine_surface.vtu").string());
  if (fs::exists(d / "fine_volume.vtu")) {
    h.fine_volume = read_volume((d / "fine_volume.vtu").string());
    h.fine_surface_to_volume.resize(static_cast<size_t>(h.fine_surface.V.rows()));
    for (size_t v = 0; v < h.fine_surface_to_volume.size(); ++v) h.fine_surface_to_volume[v] = static_cast<int>(v);
  }
  h.coarse_volume = read_volume((d / "coarse_volume.vtu").string());
  const std::string csv_path = (d / "control_points.csv").string();
  std::istringstream csv(read_file(csv_path));
  std::string line;
  std::getline(csv, line);  // header
  while (std::getline(csv, line)) {
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream ls(line);
    ControlPoint cp;
    if (!(ls >> cp.surface_vertex >> cp.coarse.tet >> cp.coarse.weights(0) >> cp.coarse.weights(1) >> cp.coarse.weights(2) >> cp.coarse.weights(3)))
      throw MeshError(csv_path, "malformed control point line '" + line + "'");
    h.control_points.push_back(cp);
  }
  const auto summary = nlohmann::json::parse(read_file((d / "summary.json").string()));
  report.self_intersections_found = summary.at("self_intersections_found").get<int>();
  report.repaired = summary.at("self_intersections_repaired").get<bool>();
  report.vertices_before_repair = summary.value("surface_vertices_before_repair", 0);
  report.flipped_triangles = summary.at("triangles_reoriented").get<int>();
  report.warnings = summary.at("warnings").get<std::vector<std::string>>();
  const auto& repair = summary.at("coarse_repair");
  h.coarse_repair = {repair.at("boundary_slivers_removed").get<int>(), repair.at("vertices_moved").get<int>(),
                     repair.at("interior_vertices_dropped").get<int>(), repair.at("remeshes").get<int>(),
                     repair.at("slivers_left").get<int>()};
  if (summary.contains("fine_repair"))  // absent in mesh folders written before the repair
    h.fine_repair = {summary["fine_repair"].at("interior_points_merged").get<int>(),
                     summary["fine_repair"].at("interior_points_not_merged").get<int>(),
                     summary["fine_repair"].value("flat_tet_points_collapsed", 0)};
  return h;
}

}  // namespace

std::string mesh_content_hash(const MeshRecipe& r) {
  // The recipe's values without its file names (a moved file is the same mesh),
  // then the files' bytes.
  nlohmann::json values = r.to_json();
  values.erase("surface");
  values.erase("coarse");
  std::ostringstream key;
  key << kCacheFormat << '|' << values.dump();
  uint64_t h = fnv1a(key.str());
  for (const std::string& f : {r.surface_file, r.coarse_file})
    if (!f.empty()) h = fnv1a(read_file(f), fnv1a("|file|", h));  // contents, not names
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
  return hex;
}

HybridMesh build_mesh_cached(const MeshRecipe& recipe, MeshReport& report, const std::string& cache_dir, bool& hit) {
  hit = false;
  if (cache_dir.empty()) return build_mesh(recipe, report);
  const fs::path entry = fs::path(cache_dir) / mesh_content_hash(recipe);
  if (fs::exists(entry / "complete")) {
    try {
      HybridMesh h = read_mesh_folder(entry.string(), report);
      hit = true;
      print_warnings(report);  // as a build would
      return h;
    } catch (const std::exception&) {
      // A damaged entry: rebuild it below.
    }
  }
  HybridMesh h = build_mesh(recipe, report);
  // Written into a staging folder and renamed, so a half-written entry is never
  // read. Best effort: a cache that cannot be written (read-only, full) only
  // costs the next run a rebuild.
  const fs::path staging = entry.string() + ".tmp" + std::to_string(::getpid());
  std::error_code ec;
  try {
    fs::remove_all(staging, ec);
    remove_stale_staging(entry);
    write_mesh_files(staging, h, report);
    write_file_atomically((staging / "complete").string(), std::string(kCacheFormat) + "\n");
    fs::remove_all(entry, ec);
    fs::rename(staging, entry, ec);
  } catch (const std::exception&) {
    ec = std::make_error_code(std::errc::io_error);
  }
  if (ec) fs::remove_all(staging, ec);  // failed, or another process won the race
  return h;
}

}  // namespace tb
