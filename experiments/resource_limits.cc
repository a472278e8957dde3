#include "resource_limits.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "cube_generator.h"
#include "mesh_checks.h"
#include "mesh_io.h"
#include "shapes.h"

namespace tb {
namespace {

// Measured on the committed runs (results/*/run.json), each rounded up:
// - the process with its libraries and the cube's meshes: 153-157 MiB
//   ("process_peak_memory_mib_after_build", results/paper/cube-pull/*);
constexpr double kProcessBytes = 160.0 * (1 << 20);
// - the meshes: (1774 - 150) MiB for 10.3 million fine tets (results/reference_convergence),
//   (277 - 150) MiB for 632 101 (results/scaling/cube-100k-*): 165-210 bytes a tet; TetGen's
//   working copy while it meshes doubles that;
constexpr double kMeshBytesPerTet = 400;
constexpr double kMeshBytesPerSurfaceVertex = 1000;  // the surface, its checks and the coarse selection
// - the direct solve's factor: 2.83 million nonzeros for 9342 dofs (cube, METIS), 1.78 million
//   for 10 212 (liver, AMD) ("factor_nonzeros"): 8-15 dofs^(4/3), nested dissection's growth in 3-D;
constexpr double kFactorNonzerosPerDof43 = 16;
constexpr double kBytesPerFactorNonzero = 12;  // a double and its share of the supernodes' indices
// - the stiffness matrix: 3 x 3 blocks of about 15 nodes a row, a double and an index each;
constexpr double kStiffnessBytesPerDof = 45 * 12;
// - PBD and the embedding: constraints, masses and weights of a few dozen doubles a vertex.
constexpr double kSurfaceModelBytesPerVertex = 2000;

double gib(double bytes) { return bytes / (1ull << 30); }

std::string in_gib(double bytes) {
  std::ostringstream s;
  s.precision(bytes < (1ull << 30) ? 2 : 3);
  s << gib(bytes) << " GiB";
  return s.str();
}

}  // namespace

MeshSizeEstimate estimate_mesh_size(const MeshRecipe& r) {
  MeshSizeEstimate e;
  SurfaceMesh surface;
  if (r.kind == MeshRecipe::Kind::Cube) {
    surface = make_cube_surface(r.cube);
    e.size_key = "mesh.nx, ny, nz or mesh.fine_tetgen.max_volume";
  } else if (r.kind == MeshRecipe::Kind::Shape) {
    surface = make_shape_surface(r.shape);
    e.size_key = "mesh.resolution";
  } else {
    surface = read_surface(r.surface_file, r.unit_scale);
    e.size_key = "mesh.surface (a coarser surface)";
  }
  e.surface_volume = std::abs(enclosed_volume(surface));
  // Each level splits every triangle in four: V' = V + E = 4V - 6 on a closed surface.
  e.surface_vertices = static_cast<double>(surface.V.rows()) * std::pow(4.0, r.refine_levels);
  const double max_volume = r.build.fine_tetgen.max_volume * std::pow(8.0, -r.refine_levels);
  e.fine_tets = 7 * e.surface_vertices;
  if (max_volume > 0) e.fine_tets = std::max(e.fine_tets, 2 * e.surface_volume / max_volume);
  e.fine_nodes = e.fine_tets / 4;
  if (r.refine_levels > 0) e.size_key = "mesh.refine_levels";
  return e;
}

double estimate_case_bytes(const ModelRun& run, const MeshSizeEstimate& size, std::string& what) {
  const double dofs = 3 * size.fine_nodes;
  const double mesh = kMeshBytesPerTet * size.fine_tets + kMeshBytesPerSurfaceVertex * size.surface_vertices;
  const double stiffness = kStiffnessBytesPerDof * dofs;
  const double factor = kBytesPerFactorNonzero * kFactorNonzerosPerDof43 * std::pow(dofs, 4.0 / 3);
  double model = 0;
  what = "the meshes";
  if (run.model == "fem" || run.model == "condensed") {
    const bool direct = run.model == "condensed" || run.parameters.choice("solver") != "iterative";
    model = stiffness + (direct ? factor : stiffness);
    what = direct ? "the fine FEM's factorisation" : "the fine FEM's stiffness and preconditioner";
    if (run.model == "condensed" && run.parameters.choice("precompute") == "surface_vertices") {
      // One displacement of every surface vertex per unit force at every surface
      // vertex: (3 n)^2 doubles (models/condensed: "response_memory_mib").
      const double responses = 72 * size.surface_vertices * size.surface_vertices;
      model += responses;
      if (responses > factor) what = "the precomputed responses, 72 n^2 bytes for n surface vertices";
    }
  } else if (run.model == "fem_distributed") {
    model = 2 * stiffness;  // an iterative solve, shared among the ranks: one rank's bound
    what = "the distributed FEM's matrices";
  } else {
    model = kSurfaceModelBytesPerVertex * size.surface_vertices;  // pbd, hybrid, embedded (coarse FEM: small)
    if (model > mesh) what = "the surface model";
  }
  return kProcessBytes + mesh + model;
}

double available_memory_bytes() {
  std::ifstream in("/proc/meminfo");
  std::string key;
  double kib = 0;
  std::string unit;
  while (in >> key >> kib >> unit)
    if (key == "MemAvailable:") return kib * 1024;
  return 0;
}

void check_memory(const Experiment& e, const std::string& only_scenario, const std::string& only_case,
                  double limit_bytes, const std::string& limit_source) {
  if (!(limit_bytes > 0)) return;
  for (const Scenario& s : e.scenarios) {
    if (!only_scenario.empty() && only_scenario != s.name) continue;
    MeshSizeEstimate size;
    try {
      size = estimate_mesh_size(s.mesh);
    } catch (const std::exception&) {
      continue;  // a surface file that cannot be read: the mesh build reports it, case by case
    }
    for (const ModelRun& run : s.models) {
      if (!only_case.empty() && only_case != run.case_name && only_case != run.model) continue;
      std::string what;
      const double need = estimate_case_bytes(run, size, what);
      if (need <= limit_bytes) continue;
      std::ostringstream msg;
      msg.precision(3);
      msg << s.file << ": scenario '" << s.name << "', case '" << run.case_name << "': needs about " << in_gib(need)
          << " (" << what << "; " << size.surface_vertices << " surface vertices, about " << size.fine_tets
          << " fine tets), more than the " << in_gib(limit_bytes) << " of " << limit_source << "; change "
          << size.size_key << (run.model == "condensed" ? ", or the case's precompute" : "")
          << " (estimates: docs/robustness.md)";
      throw std::runtime_error(msg.str());
    }
  }
}

}  // namespace tb
