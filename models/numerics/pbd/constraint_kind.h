// A kind of PBD constraint (paper 1.4: stretch, eqs. 14-18; bending, eqs. 19-26)
// as data: its name, arity (vertices per constraint), rest values per constraint,
// how its constraints are built on a surface, its scalar reference projection,
// its batched SIMD kernel compiled for every instruction set and precision, its
// XPBD compliance from the material (Macklin, Mueller, Chentanez 2016) and its
// stiffness parameter (<name>_stiffness). The kinds are listed once
// (constraint_kinds.cc) and the batches, the sweeps and the solver take them from
// that table in its order. A kind is written as a struct of static members and
// made into a ConstraintKind by define_constraint_kind (define_constraint_kind.h);
// docs/extending.md walks through adding one.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <string>
#include <vector>

#include "batch_layout.h"
#include "constraints.h"
#include "instruction_set.h"
#include "mesh_types.h"

namespace tb::pbd {

struct ConstraintKind;

/// The constraints of one kind: #C rows of `arity` vertex indices and of the
/// kind's rest values.
struct KindConstraints {
  /// `count` constraints of `kind`, all vertices 0 and rest values 0.
  explicit KindConstraints(const ConstraintKind& kind, Eigen::Index count = 0);
  const ConstraintKind* kind;
  Eigen::Matrix<int, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> vertices;  ///< #C by arity
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> rest;   ///< #C by rest values
  Eigen::Index size() const { return vertices.rows(); }
  /// `count` rows of vertices and rest values (contents as Eigen's resize leaves them).
  void resize(Eigen::Index count);
};

/// Every constraint of a surface, kind by kind in the order of the table it was
/// built from (build_constraints, constraint_kinds.h).
struct ConstraintSet {
  std::vector<KindConstraints> kinds;
  /// The constraints of the kind named `name` (std::invalid_argument if none).
  const KindConstraints& of(const std::string& name) const;
  KindConstraints& of(const std::string& name);
};

/// The shell the surface stands for in XPBD's compliances (xpbd_compliance.h).
struct ShellMaterial {
  double youngs_modulus;  ///< E, Pa
  double poisson_ratio;   ///< nu
  double thickness;       ///< h, m
};

/// One scalar Gauss-Seidel pass over one kind's constraints with its reference
/// projection (PBD: `stiffness`) or its XPBD update (`alpha_tilde`, `lambda`), in
/// `order` (reversed if asked), each correction added before the next constraint.
struct ScalarPass {
  double* x;                            ///< rows of kPositionStride numbers (aligned_rows.h)
  const int* row_of;                    ///< each vertex's row of x; null: the vertex's own index
  const Eigen::VectorXd& inverse_mass;  ///< #V, by vertex
  const KindConstraints& constraints;   ///< vertex indices
  const std::vector<int>& order;        ///< constraint rows, the batches' order
  ProjectionOptions options;
  double stiffness;                    ///< PBD
  const Eigen::VectorXd* alpha_tilde;  ///< XPBD: alpha / h^2 per constraint row
  Eigen::VectorXd* lambda;             ///< XPBD: the multiplier per constraint row
  CorrectionRecord* record = nullptr;  ///< the corrections to sum (batch_layout.h), or null
};

/// A kind's batched kernel in precision S, one function per instruction set
/// (indexed by index(isa); batch_kernels.h compiles them).
template <class S>
struct BatchKernels {
  /// Projects batches [begin, end) of `kind` at x in order (or reversed), each
  /// written back before the next.
  using Sweep = void (*)(S* x, const KindSweep<S>& kind, size_t begin, size_t end, bool reverse);
  /// The corrections of every constraint of `kind` at x, nothing moved: row
  /// order[k] of `corrections` (3 per vertex) gets the k-th constraint of the batches.
  using Corrections = void (*)(const S* x, const KindSweep<S>& kind, const std::vector<int>& order,
                               Eigen::MatrixXd& corrections);
  Sweep sweep[kInstructionSetCount];
  Corrections corrections[kInstructionSetCount];
  /// A constraint's inverse masses (arity of them) turned, in place, into the
  /// numbers per slot its kernel takes (constant per constraint).
  void (*slot_weights)(S* w);
};

struct ConstraintKind {
  const char* name;            ///< [a-z_]+, unique in a table
  int arity;                   ///< vertices per constraint
  int rest_values;             ///< rest values per constraint
  const char* stiffness_unit;  ///< of 1 / compliance, in run.json names: "N_per_m", "N_m"
  /// Its constraints on a closed surface at rest: `constraints` arrives empty.
  void (*build)(const SurfaceMesh& rest, KindConstraints& constraints);
  /// The scalar reference projection of one constraint (reference_projections.h
  /// style): p, w and corr hold `arity` entries, rest `rest_values`. False (zero
  /// corrections) when it moves nothing.
  bool (*reference)(const Vec3* p, const double* w, const double* rest, double stiffness,
                    const ProjectionOptions& options, Vec3* corr);
  /// ScalarPass with `reference` (PBD) and with the XPBD update (Macklin et al.
  /// eqs. 17-18), each compiled for this kind.
  void (*reference_pass)(const ScalarPass& pass, bool reverse);
  void (*xpbd_pass)(const ScalarPass& pass, bool reverse);
  /// XPBD compliance alpha per constraint row, at the rest shape the constraints
  /// were built from (throws std::invalid_argument where none can be derived).
  Eigen::VectorXd (*compliance)(const SurfaceMesh& rest, const KindConstraints& constraints,
                                const ShellMaterial& material);
  BatchKernels<double> double_kernels;
  BatchKernels<float> single_kernels;

  template <class S>
  const BatchKernels<S>& kernels() const {
    return for_precision<S>(double_kernels, single_kernels);
  }
  /// Its PBD parameter: "<name>_stiffness", in [0, 1].
  std::string stiffness_parameter() const { return std::string(name) + "_stiffness"; }
};

/// Kinds in the order a sweep projects them.
using KindTable = std::vector<const ConstraintKind*>;

}  // namespace tb::pbd
