// The stretch constraint of paper 1.4, one per surface edge: C = |p1 - p2| - L
// (eq. 14), L the edge's rest length, projected by eqs. (15)-(18). Its kernel is
// projection_kernels.h's, its reference projection and XPBD update
// reference_projections.h's, its compliance xpbd_compliance.h's (Van Gelder 1998).
#include "define_constraint_kind.h"
#include "projection_kernels.h"
#include "reference_projections.h"
#include "surface_edges.h"
#include "xpbd_compliance.h"

namespace tb::pbd {
namespace {

using lanes::Triple;

struct Stretch {
  static constexpr const char* kName = "stretch";
  static constexpr int kArity = 2, kRestValues = 1;
  static constexpr const char* kStiffnessUnit = "N_per_m";

  /// One constraint per edge, (min, max) vertex, in the edges' order.
  static void build(const SurfaceMesh& s, KindConstraints& c) {
    const EdgeTriangles edges = edge_triangles(s);
    c.resize(static_cast<Eigen::Index>(edges.size()));
    Eigen::Index i = 0;
    for (const auto& edge : edges) {
      const auto& [a, b] = edge.first;
      c.vertices(i, 0) = a;
      c.vertices(i, 1) = b;
      c.rest(i, 0) = (s.V.row(a) - s.V.row(b)).norm();
      ++i;
    }
  }

  /// The kernel takes the inverse-mass shares w_i / (w_1 + w_2) (stretch_shares).
  template <class S>
  static void slot_weights(S* w) {
    kernels::stretch_shares(w[0], w[1], w[0], w[1]);
  }

  template <class T>
  static TB_PBD_INLINE void project(const Triple<T> p[2], const T share[2], const T rest[1], double stiffness,
                                    const ProjectionOptions&, Triple<T> corr[2]) {
    kernels::project_stretch(p[0], share[0], p[1], share[1], rest[0], stiffness, corr[0], corr[1]);
  }

  static bool reference(const Vec3 p[2], const double w[2], const double rest[1], double stiffness,
                        const ProjectionOptions&, Vec3 corr[2]) {
    return reference::project_stretch(p[0], w[0], p[1], w[1], rest[0], stiffness, corr[0], corr[1]);
  }

  static bool xpbd(const Vec3 p[2], const double w[2], const double rest[1], double alpha_tilde, double& lambda,
                   const ProjectionOptions&, Vec3 corr[2]) {
    return reference::xpbd_stretch(p[0], w[0], p[1], w[1], rest[0], alpha_tilde, lambda, corr[0], corr[1]);
  }

  static Eigen::VectorXd compliance(const SurfaceMesh& rest, const KindConstraints& c, const ShellMaterial& m) {
    return stretch_compliances(rest, c, m.youngs_modulus, m.thickness);
  }
};

}  // namespace

const ConstraintKind& stretch_kind() {
  static const ConstraintKind kind = define_constraint_kind<Stretch>();
  return kind;
}

}  // namespace tb::pbd
