// `tissuebench export`, narrated:
//  1. Meshes: each selected scenario's meshes are built as the runner builds them
//     (build_mesh_cached, through the same cache), and what the scenario places
//     relative to them resolved and checked (resolve_on_mesh, check_on_mesh).
//  2. Points: the role's committed observation points (observation_points.h), placed
//     on that surface where the files hold no coordinates.
//  3. Files: written into a staging folder per scenario; only when every scenario
//     is staged are they moved into place (staged_folder.h), so a failure on the
//     tenth scenario leaves none of the nine before it half-updated.
#include "problem_package.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "atomic_file.h"
#include "data_dir.h"
#include "lame_parameters.h"
#include "material_laws.h"
#include "mesh_error.h"
#include "mesh_io.h"
#include "mesh_recipe.h"
#include "staged_folder.h"
#include "stl_writer.h"
#include "tool_placement.h"

namespace tb {
namespace fs = std::filesystem;

namespace {

/// The law the converged answer is computed with: Newton on the neo-Hookean law,
/// the suite's reference case (experiments/scenarios/suite/cube.base.json) and the
/// reference study's (docs/reference_convergence.md).
constexpr const char* kAnswerLaw = "neo_hookean";
/// The frame interval when no case of the scenario has a time step: the models' default.
constexpr double kDefaultTimeStep = 0.01;

/// A coordinate in JSON: a number, or null for an unbounded side of a box (JSON has
/// no infinity).
nlohmann::json coordinate(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); }
nlohmann::json vec(const Eigen::Vector3d& v) { return {coordinate(v.x()), coordinate(v.y()), coordinate(v.z())}; }

/// "frame,x,y,z" rows of `value_at(frame)` for frames 0..frames-1.
template <class ValueAt>
std::string frames_csv(int frames, ValueAt value_at) {
  std::ostringstream os;
  os << std::setprecision(17) << "frame,x,y,z\n";
  for (int f = 0; f < frames; ++f) {
    const Eigen::Vector3d v = value_at(f);
    os << f << ',' << v.x() << ',' << v.y() << ',' << v.z() << '\n';
  }
  return os.str();
}

/// Points as "id,[patch,]x,y,z" rows.
std::string points_csv(const std::vector<std::string>& id, const std::vector<std::string>* patch, const Points& X) {
  std::ostringstream os;
  os << std::setprecision(17) << (patch ? "id,patch,x,y,z\n" : "id,x,y,z\n");
  for (size_t k = 0; k < id.size(); ++k) {
    const auto r = static_cast<Eigen::Index>(k);
    os << id[k] << ',';
    if (patch) os << (*patch)[k] << ',';
    os << X(r, 0) << ',' << X(r, 1) << ',' << X(r, 2) << '\n';
  }
  return os.str();
}

std::string load_file(size_t k) { return "load_" + std::to_string(k) + ".csv"; }
std::string tool_file(size_t k) { return "tool_" + std::to_string(k) + ".csv"; }
std::string held_file(size_t k) { return "tool_" + std::to_string(k) + "_vertices.csv"; }

/// A "vertex" column of surface vertex indices.
std::string vertex_csv(const std::vector<int>& vertices) {
  std::ostringstream os;
  os << "vertex\n";
  for (int v : vertices) os << v << '\n';
  return os.str();
}

/// The surface vertices the support holds, ascending.
std::vector<int> support_vertices(const Scenario& s, const SurfaceMesh& surface) {
  const std::vector<char> clamped = s.support.select(surface.V);
  std::vector<int> out;
  for (size_t v = 0; v < clamped.size(); ++v)
    if (clamped[v]) out.push_back(static_cast<int>(v));
  return out;
}

/// Whether surface vertex v is volume node v for every v (volume_ordering.h keeps
/// the surface's vertices first).
bool surface_vertices_first(const HybridMesh& mesh) {
  for (size_t v = 0; v < mesh.fine_surface_to_volume.size(); ++v)
    if (mesh.fine_surface_to_volume[v] != static_cast<int>(v)) return false;
  return !mesh.fine_surface_to_volume.empty();
}

}  // namespace

std::string default_schema_dir() { return (fs::path(source_dir()) / "docs" / "schemas").string(); }

int package_frames(const Scenario& s) { return std::max({1, s.static_frames, s.changing_frames()}); }

double package_time_step(const Scenario& s) {
  const ModelRun* chosen = nullptr;
  for (const ModelRun& run : s.models) {
    if (!run.parameters.to_json().contains("time_step")) continue;
    if (run.model == "fem_dynamic") return run.parameters.number("time_step");
    if (!chosen) chosen = &run;
  }
  return chosen ? chosen->parameters.number("time_step") : kDefaultTimeStep;
}

nlohmann::json problem_json(const Scenario& s, const HybridMesh& mesh, const ObservationPoints& points) {
  const int frames = package_frames(s);
  const LoadCase load_case = s.load_case();
  FrameLoads last;
  s.loads_at(frames - 1, last);
  nlohmann::json j;
  j["format"] = kProblemFormat;
  j["scenario"] = s.name;
  // The role that scores the package: a finer study's role takes its base role's
  // points and answer (observation_role).
  j["role"] = points.role.empty() ? s.role : points.role;
  if (j["role"] != s.role) j["scenario_role"] = s.role;
  j["description"] = s.description;
  j["scenario_file"] = shown_path(s.file);
  j["units"] = {{"length", "m"}, {"force", "N"}, {"time", "s"}, {"stress", "Pa"}, {"density", "kg/m^3"}};
  j["meshes"] = {
      {"surface",
       {{"obj", "surface.obj"},
        {"stl", "surface.stl"},
        {"vertices", mesh.fine_surface.V.rows()},
        {"triangles", mesh.fine_surface.F.rows()},
        {"orientation", "counter-clockwise seen from outside; vertex indices 0-based in the OBJ's order"}}},
      {"volume",
       {{"vtu", "volume.vtu"},
        {"gmsh", "volume.msh"},
        {"nodes", mesh.fine_volume.V.rows()},
        {"tets", mesh.fine_volume.T.rows()},
        {"surface_vertices_first", surface_vertices_first(mesh)},
        {"surface_vertex_field", "volume.vtu's point field surface_vertex: the surface vertex a node is, -1 inside"}}}};
  const MaterialLawInfo& law = find_material_law(kAnswerLaw);
  const LameParameters lame = lame_parameters(s.material);
  j["material"] = {{"law", law.name},
                   {"energy_density", law.description},
                   {"answer_computed_with",
                    "Newton's method on this law (fem, solver newton) on a finer mesh of the same body: the "
                    "reference study's finest run (docs/reference_convergence.md)"},
                   {"youngs_modulus", s.material.youngs_modulus},
                   {"poisson_ratio", s.material.poisson_ratio},
                   {"density", s.material.density},
                   {"lame_mu", lame.mu},
                   {"lame_lambda", lame.lambda},
                   {"lame_from", "mu = E / (2 (1 + nu)), lambda = E nu / ((1 + nu)(1 - 2 nu))"}};
  nlohmann::json definition = {{"box", {{"min", vec(s.support.min)}, {"max", vec(s.support.max)}}},
                               {"meaning",
                                "every node whose rest position lies in the box (null: unbounded) is held "
                                "fixed, interior nodes of a volume too (the lowest fraction of the height is "
                                "a slab); support_vertices.csv lists the surface's"}};
  if (s.support_lowest_fraction >= 0) definition["lowest_fraction"] = s.support_lowest_fraction;
  j["support"] = {{"definition", definition},
                  {"vertices", "support_vertices.csv"},
                  {"count", support_vertices(s, mesh.fine_surface).size()}};
  j["loads"] = nlohmann::json::array();
  for (size_t k = 0; k < load_case.loads.size(); ++k) {
    const Load& l = load_case.loads[k];
    nlohmann::json e = {{"name", "load_" + std::to_string(k)},
                        {"key", l.key},
                        {"type", name(l.kind)},
                        {"path", load_file(k)},
                        {"value", l.kind == LoadKind::BodyForce ? "acceleration (m/s^2)" : "force (N)"},
                        {"last_value", vec(last.values[k])}};
    if (l.kind != LoadKind::BodyForce) e["point"] = vec(l.point);
    if (l.kind == LoadKind::SurfaceTraction) {
      e["radius"] = l.radius;
      e["meaning"] = "the total force spread uniformly over the surface within radius of point";
    }
    if (l.kind == LoadKind::BodyForce) {
      e["meaning"] = "the force density rho g everywhere";
      j["gravity"] = vec(last.values[k]);
    }
    j["loads"].push_back(e);
  }
  j["tools"] = nlohmann::json::array();
  for (size_t k = 0; k < s.tools.size(); ++k) {
    const Tool& t = s.tools[k].tool;
    nlohmann::json e = to_json(s.tools[k]);
    e.erase("schedule");  // the path file holds every frame's value
    e["name"] = "tool_" + std::to_string(k);
    e["path"] = tool_file(k);
    e["value"] = t.kind == ToolKind::Sphere ? "the sphere's centre (m)" : "the displacement of what it holds (m)";
    if (t.kind == ToolKind::Sphere) e["first_centre"] = vec(t.point);
    e["held_vertices"] = tool_vertices(t, mesh.fine_surface, s.support).size();
    if (t.kind != ToolKind::Sphere) e["held_vertices_file"] = held_file(k);
    j["tools"].push_back(e);
  }
  j["time"] = {{"dt", package_time_step(s)},
               {"frames", frames},
               {"ramp_frames", s.changing_frames()},
               {"meaning",
                "frames 0..frames-1, dt apart; each load and tool takes its path file's value; the "
                "answer is the static equilibrium under the last frame's values (a dynamic simulator "
                "reports it once settled)"}};
  nlohmann::json obs = {{"surface_points", "observation_points.csv"},
                        {"surface_count", points.surface.rows()},
                        {"frames", {frames - 1}},
                        {"source", points.source}};
  if (points.interior.rows() > 0) {
    obs["interior_points"] = "observation_interior.csv";
    obs["interior_count"] = points.interior.rows();
  }
  j["observation"] = obs;
  nlohmann::json files = {"submission.json", "displacements.csv"};
  if (!s.tools.empty()) files.push_back("forces.csv");
  j["submission"] = {{"format", kSubmissionFormat}, {"files", files}, {"schema", "submission.schema.json"}};
  return j;
}

void write_problem_files(const Scenario& s, const HybridMesh& mesh, const ObservationPoints& points,
                         const std::string& dir, const std::string& schema_dir) {
  if (mesh.fine_volume.T.rows() == 0)
    throw std::runtime_error(shown_path(s.file) + ": scenario '" + s.name +
                             "' has no fine tet volume (mesh.build_fine_volume false): the package needs one");
  const fs::path d(dir);
  auto path = [&](const std::string& name) { return (d / name).string(); };
  // Schemas first: a missing one stops before the large files.
  for (const char* schema : {"problem.schema.json", "submission.schema.json"}) {
    const std::string from = (fs::path(schema_dir) / schema).string();
    std::error_code ec;
    if (!fs::is_regular_file(from, ec)) throw std::runtime_error(from + ": not found (the package copies it)");
    write_file_atomically(path(schema), read_file(from));
  }
  const int frames = package_frames(s);
  write_obj(path("surface.obj"), mesh.fine_surface);
  write_stl(path("surface.stl"), mesh.fine_surface, s.name);
  Eigen::VectorXd surface_vertex = Eigen::VectorXd::Constant(mesh.fine_volume.V.rows(), -1);
  for (size_t v = 0; v < mesh.fine_surface_to_volume.size(); ++v)
    surface_vertex(mesh.fine_surface_to_volume[v]) = static_cast<double>(v);
  write_volume_vtu(path("volume.vtu"), mesh.fine_volume, {{"surface_vertex", surface_vertex}});
  write_gmsh41(path("volume.msh"), mesh.fine_volume);

  write_file_atomically(path("support_vertices.csv"), vertex_csv(support_vertices(s, mesh.fine_surface)));
  // What each tool holds, as tool_placement.h chooses it: a simulator need not redo the
  // choice (a grasp's radius, a plate's box) to hold the same vertices.
  for (size_t k = 0; k < s.tools.size(); ++k)
    if (s.tools[k].tool.kind != ToolKind::Sphere)
      write_file_atomically(path(held_file(k)),
                            vertex_csv(tool_vertices(s.tools[k].tool, mesh.fine_surface, s.support)));

  std::vector<FrameLoads> per_frame(static_cast<size_t>(frames));
  for (int f = 0; f < frames; ++f) s.loads_at(f, per_frame[static_cast<size_t>(f)]);
  for (size_t k = 0; k < per_frame.front().values.size(); ++k)
    write_file_atomically(path(load_file(k)),
                          frames_csv(frames, [&](int f) { return per_frame[static_cast<size_t>(f)].values[k]; }));
  for (size_t k = 0; k < per_frame.front().tool_values.size(); ++k)
    write_file_atomically(path(tool_file(k)),
                          frames_csv(frames, [&](int f) { return per_frame[static_cast<size_t>(f)].tool_values[k]; }));

  write_file_atomically(path("observation_points.csv"),
                        points_csv(points.surface_id, &points.surface_patch, points.surface));
  if (points.interior.rows() > 0)
    write_file_atomically(path("observation_interior.csv"), points_csv(points.interior_id, nullptr, points.interior));
  write_file_atomically(path("problem.json"), problem_json(s, mesh, points).dump(1) + "\n");
}

std::string stage_problem_package(const Scenario& s, const HybridMesh& mesh, const ObservationPoints& points,
                                  const std::string& dir, const std::string& schema_dir) {
  const fs::path staging = staging_folder(dir);
  remove_stale_staging(dir);
  std::error_code ec;
  fs::remove_all(staging, ec);
  fs::create_directories(staging, ec);
  if (ec) throw std::runtime_error(staging.string() + ": cannot create the staging folder (" + ec.message() + ")");
  try {
    write_problem_files(s, mesh, points, staging.string(), schema_dir);
  } catch (...) {
    fs::remove_all(staging, ec);
    throw;
  }
  return staging.string();
}

void write_problem_package(const Scenario& s, const HybridMesh& mesh, const ObservationPoints& points,
                           const std::string& dir, const std::string& schema_dir) {
  replace_folder(stage_problem_package(s, mesh, points, dir, schema_dir), dir);
}

std::vector<std::string> export_problem_packages(const Experiment& e, const std::string& file,
                                                 const ExportOptions& opt) {
  auto say = [&](const std::string& line) {
    if (opt.progress) opt.progress(line);
  };
  std::vector<const Scenario*> selected;
  std::string known;
  for (const Scenario& s : e.scenarios) {
    if (opt.only_scenario.empty() || s.name == opt.only_scenario || s.role == opt.only_scenario) selected.push_back(&s);
    known += (known.empty() ? "" : ", ") + s.name + (s.role.empty() ? "" : " (" + s.role + ")");
  }
  if (selected.empty())
    throw std::runtime_error(file + ": no scenario named '" + opt.only_scenario + "' (its scenarios: " + known + ")");
  if (opt.out_dir.empty()) throw std::runtime_error(file + ": --out: no folder given");
  {
    std::error_code ec;
    fs::create_directories(opt.out_dir, ec);
    if (ec || !fs::is_directory(opt.out_dir))
      throw std::runtime_error(opt.out_dir + ": cannot create the output folder (" +
                               (ec ? ec.message() : std::string("a file is in the way")) + ")");
  }
  std::vector<std::pair<fs::path, fs::path>> staged;  // staging, destination
  auto discard = [&] {
    std::error_code ec;
    for (const auto& [staging, dir] : staged) fs::remove_all(staging, ec);
  };
  try {
    for (const Scenario* given : selected) {
      say(given->name + ": preparing meshes");
      MeshReport report;
      bool hit = false;
      const HybridMesh mesh = build_mesh_cached(given->mesh, report, opt.mesh_cache_dir, hit);
      say(given->name + ": " + std::to_string(mesh.fine_surface.V.rows()) + " surface vertices, " +
          std::to_string(mesh.fine_volume.T.rows()) + " fine tets" + (hit ? " (from the mesh cache)" : ""));
      Scenario s = *given;
      resolve_on_mesh(s, mesh.fine_surface);
      check_on_mesh(s, mesh.fine_surface);
      const ObservationPoints points = s.role.empty()
                                           ? scenario_observation_points(s, mesh.fine_surface)
                                           : read_observation_points(opt.observation_points_dir, s, mesh.fine_surface);
      const fs::path dir = fs::path(opt.out_dir) / s.name;
      staged.emplace_back(stage_problem_package(s, mesh, points, dir.string(), opt.schema_dir), dir);
      say(s.name + ": staged " + std::to_string(points.surface.rows()) + " surface and " +
          std::to_string(points.interior.rows()) + " interior observation points, " +
          std::to_string(package_frames(s)) + " frames");
    }
  } catch (const std::exception& ex) {
    discard();
    throw std::runtime_error(one_line(file + ": " + ex.what()));
  }
  std::vector<std::string> written;
  for (const auto& [staging, dir] : staged) {
    replace_folder(staging, dir);
    written.push_back(dir.string());
    say(dir.string() + ": written");
  }
  return written;
}

}  // namespace tb
