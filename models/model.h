// The one seam every deformation model plugs into (docs/architecture.md). A model answers in
// one currency: the displacement of every fine-surface vertex, in the fine
// surface's vertex order, so all models compare vertex by vertex.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "load_case.h"
#include "material.h"
#include "mesh_types.h"
#include "parameters.h"

namespace tb {

/// Everything a model needs to set itself up. The mesh outlives the model.
struct Problem {
  const HybridMesh* mesh = nullptr;
  Material material;
  LoadCase load_case;     ///< the support, the loads and the tools, placed in the rest configuration
  Parameters parameters;  ///< the model's own, resolved against its specs
  /// #P by 3 interior points whose displacement is observed (a tumour, a bead);
  /// inside the body (the runner checks).
  Points probes;
};

/// A contact tool's (a sphere's) state after a frame; zero for the other tools.
struct ToolContact {
  int points = 0;              ///< surface points in contact (FEM: active nodes; PBD, hybrid: vertices on the sphere at the end of the frame)
  double area = 0;             ///< m^2: the contact points' vertex areas (ContactArea, tool_placement.h)
  double max_penetration = 0;  ///< m: the deepest surface vertex inside the sphere after the frame (0: none)
};

/// #V_surface by 3 displacements of the fine-surface vertices.
using Displacements = Points;

/// Named phases of a frame (docs/design.md: named timing phases), the same names in every model; the
/// runner writes each one's median and p95 to timings.json.
namespace phase {
inline constexpr const char* kSolve = "solve";               ///< a static model's solve (fem)
inline constexpr const char* kCoarseSolve = "coarse_solve";  ///< hybrid: coarse K u = f, eq. (11); embedded: its coarse step
inline constexpr const char* kMapping = "mapping";           ///< hybrid: control points from the coarse u, eq. (33); embedded: the surface
inline constexpr const char* kProjection = "projection";     ///< PBD: pins (eq. 33) and constraint sweeps
inline constexpr const char* kIntegration = "integration";   ///< PBD: eqs. (31)-(32), (34)-(35), displacements
}  // namespace phase

/// How long one phase of the last frame took.
struct PhaseTime {
  const char* name;  ///< one of tb::phase
  double ms = 0;
};

class Model {
 public:
  virtual ~Model() = default;
  /// Meshes, material, support, where each load acts; precomputation (assembly,
  /// factorisation ...). Only loads of the kinds ModelInfo::loads lists arrive.
  virtual void setup(const Problem& problem) = 0;
  /// One frame under the loads' values (one per problem.load_case.loads): a static
  /// solve (FEM) or one time step (PBD, hybrid). Allocates nothing on the heap
  /// after the first frame (tests/models/allocation_free_frames_test.cc checks every
  /// registered model; docs/extending.md).
  virtual void step(const FrameLoads& loads) = 0;
  /// Displacement of every fine-surface vertex after the last step.
  virtual const Displacements& surface_displacement() const = 0;
  /// After step(): the force the tissue exerts on each tool (LoadCase::tools order)
  /// and then on the support, N: #tools + 1. Null when the model does not measure
  /// it (ModelInfo::reactions is empty).
  virtual const std::vector<Eigen::Vector3d>* reaction_forces() const { return nullptr; }
  /// After step(): per tool (LoadCase::tools order) its contact state (a sphere's;
  /// zeros for the other tools). Null when the model takes no contact tool.
  virtual const std::vector<ToolContact>* tool_contacts() const { return nullptr; }
  /// After step(): the displacement at each Problem::probes point (#P by 3). Null
  /// when the model has no volume to interpolate in (ModelInfo::probes is empty).
  virtual const Points* probe_displacements() const { return nullptr; }
  /// Solver iterations in the last step, where meaningful (else 0).
  virtual int last_iterations() const { return 0; }
  /// Facts about how the model set itself up and maps the load (strategies chosen,
  /// factor sizes, how far the load point was from the mesh it was mapped into, the
  /// vector instruction set of a SIMD kernel), written into run.json beside the
  /// parameters. Called after step().
  virtual nlohmann::json report() const { return nlohmann::json::object(); }
  /// The phases of the last step() with their times, in the order run (empty for a
  /// model that does not split its frame). The list is fixed at setup: reading and
  /// updating it allocates nothing.
  virtual const std::vector<PhaseTime>& last_phase_times() const {
    static const std::vector<PhaseTime> none;
    return none;
  }
};

/// A registered model: its name, what it is, its parameters, the loads it takes
/// and how to make one.
struct ModelInfo {
  std::string name;  ///< [a-z0-9_]+, unique (checked at registration)
  std::string description;
  bool dynamic = false;  ///< advances in time: run until steady (else one solve per frame)
  /// Solves one case over every MPI rank together (MPI_COMM_WORLD, collective calls):
  /// under mpirun its cases are run by all ranks at once, never dealt to one
  /// (experiments/runner.h, RunOptions::processes).
  bool spans_ranks = false;
  std::vector<ParameterSpec> parameters;
  std::function<std::unique_ptr<Model>()> create;
  std::vector<LoadKind> loads = {LoadKind::PointForce};  ///< the kinds of load it takes
  std::vector<ToolKind> tools;                           ///< the kinds of tool it takes
  /// How it holds a tool's surface (written in run.json and `tissuebench models`).
  std::string tools_how;
  /// How it measures the reaction forces; empty: it does not (reaction_forces() null).
  std::string reactions;
  /// How it gives interior probes' displacements; empty: it has no volume.
  std::string probes;
  /// Refusals that depend on its parameters, not on the kinds above (a solver
  /// without contact, a coarse volume without pads): throws std::invalid_argument
  /// naming the tool and the parameter; null when the kinds say everything. Called
  /// before setup (check_supported), so a suite lists such a case as not run, not
  /// as failed; the model's setup makes the same check for a direct caller.
  std::function<void(const Parameters& resolved, const LoadCase&)> check_case;
  bool takes(LoadKind kind) const;
  bool takes(ToolKind kind) const;
};

/// Every model, in one explicit list (models/registry.cc). The first call checks
/// the names (validate_registry) and throws std::logic_error naming the offender.
const std::vector<ModelInfo>& registered_models();
/// The model called `name`; throws std::invalid_argument listing the known names.
const ModelInfo& find_model(const std::string& name);
/// Throws std::logic_error unless every name is [a-z0-9_]+ and unique: names
/// become folder names and test names (GoogleTest refuses a hyphen there).
void validate_registry(const std::vector<ModelInfo>& models);

/// Throws std::invalid_argument, before anything is set up, when `model` does not
/// take a load or a tool of `load_case`: "model 'pbd' does not take
/// surface_traction loads (loads[1]); it takes point_force, body_force".
void check_supported(const ModelInfo& model, const LoadCase& load_case);
/// The same, then the model's check_case for its resolved `parameters`.
void check_supported(const ModelInfo& model, const Parameters& parameters, const LoadCase& load_case);

}  // namespace tb
