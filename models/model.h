// The one seam every deformation model plugs into (DESIGN.md). A model answers in
// one currency: the displacement of every fine-surface vertex, in the fine
// surface's vertex order, so all models compare vertex by vertex.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "mesh_types.h"
#include "parameters.h"

namespace tb {

/// Linear isotropic elastic material, SI units.
struct Material {
  double youngs_modulus = 3000;  ///< Pa
  double poisson_ratio = 0.45;
  double density = 1000;  ///< kg/m^3
};

/// Vertices whose rest position lies in [min, max] (component-wise) are clamped.
struct SupportBox {
  Eigen::Vector3d min = Eigen::Vector3d::Constant(-1e300), max = Eigen::Vector3d::Constant(1e300);
  bool contains(const Eigen::Vector3d& p) const {
    return (p.array() >= min.array()).all() && (p.array() <= max.array()).all();
  }
  /// #V flags: 1 where the row of V is clamped.
  std::vector<char> select(const Points& V) const;
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
  /// What the model wants recorded beside its results (run.json "model_statistics"),
  /// e.g. degrees of freedom and solver counts; empty by default.
  virtual nlohmann::json statistics() const { return nlohmann::json::object(); }
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
