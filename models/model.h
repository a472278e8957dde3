// The one seam every deformation model plugs into (DESIGN.md). A model answers in
// one currency: the displacement of every fine-surface vertex, in the fine
// surface's vertex order, so all models compare vertex by vertex.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "material.h"
#include "mesh_types.h"
#include "parameters.h"

namespace tb {

/// Vertices whose rest position lies in [min, max] (component-wise) are clamped.
struct SupportBox {
  Eigen::Vector3d min = Eigen::Vector3d::Constant(-1e300), max = Eigen::Vector3d::Constant(1e300);
  bool contains(const Eigen::Vector3d& p) const {
    return (p.array() >= min.array()).all() && (p.array() <= max.array()).all();
  }
  /// #V flags: 1 where the row of V is clamped.
  std::vector<char> select(const Points& V) const;
  /// select(V), checked to hold the body: at least three clamped nodes not on
  /// one line, else a std::invalid_argument naming this box, `mesh_name` and the
  /// counts (a support that leaves rigid motions free makes K singular and PBD
  /// drift). Every model calls it for every mesh it uses, before factorising.
  std::vector<char> clamp(const Points& V, const std::string& mesh_name) const;
};

/// A point force: `force` (N) acting at `point` (m) in the rest configuration.
/// With disc_radius > 0 (m) the same total force is a uniform traction on the disc
/// of that radius around `point` on the surface (models/fem/surface_load.h); 0 is
/// the paper's point load. A model without disc loads throws std::invalid_argument
/// naming load.disc_radius.
struct PointLoad {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  double disc_radius = 0;
};

/// For models that take only the paper's point load: throws std::invalid_argument
/// naming `model` and load.disc_radius unless load.disc_radius is 0.
void require_point_load(const PointLoad& load, const char* model);

/// Everything a model needs to set itself up. The mesh outlives the model.
struct Problem {
  const HybridMesh* mesh = nullptr;
  Material material;
  SupportBox support;
  Parameters parameters;  ///< the model's own, resolved against its specs
};

/// #V_surface by 3 displacements of the fine-surface vertices.
using Displacements = Points;

/// Named phases of a frame (STYLE.md 10), the same names in every model; the
/// runner writes each one's median and p95 to timings.json.
namespace phase {
inline constexpr const char* kSolve = "solve";               ///< a static model's solve (fem)
inline constexpr const char* kCoarseSolve = "coarse_solve";  ///< hybrid: coarse K u = f, eq. (11)
inline constexpr const char* kMapping = "mapping";           ///< hybrid: control points from the coarse u, eq. (33)
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
  /// Meshes, material, support; precomputation (assembly, factorisation ...).
  virtual void setup(const Problem& problem) = 0;
  /// One frame under `load`: a static solve (FEM) or one time step (PBD, hybrid).
  virtual void step(const PointLoad& load) = 0;
  /// Displacement of every fine-surface vertex after the last step.
  virtual const Displacements& surface_displacement() const = 0;
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

/// A registered model: its name, what it is, its parameters and how to make one.
struct ModelInfo {
  std::string name;
  std::string description;
  bool dynamic = false;  ///< advances in time: run until steady (else one solve per frame)
  std::vector<ParameterSpec> parameters;
  std::function<std::unique_ptr<Model>()> create;
};

/// Every model, in one explicit list (models/registry.cc).
const std::vector<ModelInfo>& registered_models();
/// The model called `name`; throws std::invalid_argument listing the known names.
const ModelInfo& find_model(const std::string& name);

}  // namespace tb
