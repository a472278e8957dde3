// Makes a ConstraintKind (constraint_kind.h) from a struct of static members, the
// one thing a new kind writes (docs/extending.md, "Adding a PBD constraint kind"):
//
//   struct Stretch {
//     static constexpr const char* kName = "stretch";        // [a-z_]+
//     static constexpr int kArity = 2, kRestValues = 1;      // vertices, rest values
//     static constexpr const char* kStiffnessUnit = "N_per_m";  // of 1 / compliance
//     static void build(const SurfaceMesh& rest, KindConstraints& c);
//     // The SIMD kernel on a batch (T: lanes) or one constraint (T: a number):
//     template <class T>
//     TB_PBD_INLINE static void project(const Triple<T> p[2], const T w[2], const T rest[1], double stiffness,
//                                       const ProjectionOptions& options, Triple<T> corr[2]);
//     // Optional: the numbers per slot the kernel takes for w (constant per constraint).
//     template <class S> static void slot_weights(S* w);
//     static bool reference(const Vec3 p[2], const double w[2], const double rest[1], double stiffness,
//                           const ProjectionOptions& options, Vec3 corr[2]);
//     static bool xpbd(const Vec3 p[2], const double w[2], const double rest[1], double alpha_tilde,
//                      double& lambda, const ProjectionOptions& options, Vec3 corr[2]);
//     static Eigen::VectorXd compliance(const SurfaceMesh& rest, const KindConstraints& c,
//                                       const ShellMaterial& material);
//   };
//   const ConstraintKind& stretch_kind() {
//     static const ConstraintKind kind = define_constraint_kind<Stretch>();
//     return kind;
//   }
//
// The file that includes this compiles the kind's kernels for every instruction
// set and precision: it needs the lane-math compile options (models/CMakeLists.txt
// gives them to numerics/pbd/*_kind.cc).
#pragma once

#include "batch_kernels.h"
#include "constraint_kind.h"
#include "scalar_passes.h"

namespace tb::pbd {

template <class K>
ConstraintKind define_constraint_kind() {
  static_assert(K::kArity >= 1 && K::kRestValues >= 0, "a constraint has vertices");
  return {K::kName,
          K::kArity,
          K::kRestValues,
          K::kStiffnessUnit,
          K::build,
          K::reference,
          scalar_pass<K, false>,
          scalar_pass<K, true>,
          K::compliance,
          batches::batch_kernels<K, double>(),
          batches::batch_kernels<K, float>()};
}

}  // namespace tb::pbd
