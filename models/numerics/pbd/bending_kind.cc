// The bending constraint of paper 1.4, one per interior edge (hinge): the
// dihedral angle between its two triangles against its rest angle, eq. (19) (or
// its signed form, ProjectionOptions::bending_angle), projected by eq. (13) with
// masses and Bridson, Marino, Fedkiw 2003's bounded gradient, within its trust
// region (constraints.h). Its kernel is projection_kernels.h's, its reference
// projection and XPBD update reference_projections.h's, its compliance
// xpbd_compliance.h's (Grinspun et al. 2003).
#include <array>
#include <vector>

#include "define_constraint_kind.h"
#include "projection_kernels.h"
#include "reference_projections.h"
#include "surface_edges.h"
#include "xpbd_compliance.h"

namespace tb::pbd {
namespace {

using lanes::Triple;

struct Bending {
  static constexpr const char* kName = "bending";
  static constexpr int kArity = 4, kRestValues = 1;
  static constexpr const char* kStiffnessUnit = "N_m";

  /// One constraint per edge shared by two triangles, in the edges' order: p1 -> p2
  /// as the first triangle traverses the edge, p3 its opposite vertex, p4 the other
  /// triangle's, so triangles (p1, p2, p3) and (p2, p1, p4) as constraints.h
  /// expects; the rest value is the signed rest angle (signed_normal_angle).
  static void build(const SurfaceMesh& s, KindConstraints& c) {
    std::vector<std::array<int, 4>> hinges;
    for (const auto& [edge, tris] : edge_triangles(s))
      if (tris.size() == 2) hinges.push_back({{tris[0][0], tris[0][1], tris[0][2], tris[1][2]}});
    c.resize(static_cast<Eigen::Index>(hinges.size()));
    for (size_t b = 0; b < hinges.size(); ++b) {
      const auto& q = hinges[b];
      const Eigen::Index i = static_cast<Eigen::Index>(b);
      for (int j = 0; j < 4; ++j) c.vertices(i, j) = q[static_cast<size_t>(j)];
      c.rest(i, 0) = signed_normal_angle(s.V.row(q[0]).transpose(), s.V.row(q[1]).transpose(),
                                         s.V.row(q[2]).transpose(), s.V.row(q[3]).transpose());
    }
  }

  template <class T>
  static TB_PBD_INLINE void project(const Triple<T> p[4], const T w[4], const T rest[1], double stiffness,
                                    const ProjectionOptions& options, Triple<T> corr[4]) {
    kernels::project_bending(p, w, rest[0], stiffness, options.bending_angle, corr);
  }

  static bool reference(const Vec3 p[4], const double w[4], const double rest[1], double stiffness,
                        const ProjectionOptions& options, Vec3 corr[4]) {
    return reference::project_bending(p[0], w[0], p[1], w[1], p[2], w[2], p[3], w[3], rest[0], stiffness, corr,
                                      options.bending_angle);
  }

  static bool xpbd(const Vec3 p[4], const double w[4], const double rest[1], double alpha_tilde, double& lambda,
                   const ProjectionOptions& options, Vec3 corr[4]) {
    return reference::xpbd_bending(p[0], w[0], p[1], w[1], p[2], w[2], p[3], w[3], rest[0], alpha_tilde, lambda, corr,
                                   options.bending_angle);
  }

  static Eigen::VectorXd compliance(const SurfaceMesh& rest, const KindConstraints& c, const ShellMaterial& m) {
    return bending_compliances(rest, c, m.youngs_modulus, m.poisson_ratio, m.thickness);
  }
};

}  // namespace

const ConstraintKind& bending_kind() {
  static const ConstraintKind kind = define_constraint_kind<Bending>();
  return kind;
}

}  // namespace tb::pbd
