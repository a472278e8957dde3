// PBD constraint functions, gradients and projections (paper 1.4) as stateless
// functions, after Bender's PositionBasedDynamics (STYLE.md 1). Each projection
// returns position corrections; the caller applies them.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

namespace tb::pbd {

using Vec3 = Eigen::Vector3d;

/// Stretch constraint, eq. (14): C = |p1 - p2| - rest_length.
double stretch_constraint(const Vec3& p1, const Vec3& p2, double rest_length);
/// Its gradients, eqs. (15)-(16). Zero when p1 == p2.
void stretch_gradient(const Vec3& p1, const Vec3& p2, Vec3& grad1, Vec3& grad2);
/// Projection, eqs. (17)-(18), scaled by stiffness in [0, 1]. Returns false (and
/// zero corrections) when both points are fixed or coincide.
inline bool project_stretch(const Vec3& p1, double w1, const Vec3& p2, double w2, double rest_length, double stiffness,
                            Vec3& corr1, Vec3& corr2);

/// Bending constraint across the edge (p1, p2) shared by two triangles with the
/// wing vertices p3 and p4, eq. (19) as intended: C = arccos(n1 . n2) - rest_angle,
/// evaluated as atan2(|n1 x n2|, n1 . n2), which is the same angle without
/// arccos's loss of accuracy (or NaN) at 0 and pi. The normals are those of eqs. (20)-(21) but
/// consistently oriented, n1 of (p1, p2, p3) and n2 of (p2, p1, p4), so a flat pair
/// has angle 0 (eqs. 20-21 as printed give pi there, where arccos is singular).
/// A degenerate triangle (zero normal) gives C = 0.
double bending_constraint(const Vec3& p1, const Vec3& p2, const Vec3& p3, const Vec3& p4, double rest_angle);
/// The angle between the two triangles' normals, arccos(n1 . n2), in [0, pi]
/// (0 when coplanar and unfolded).
double normal_angle(const Vec3& p1, const Vec3& p2, const Vec3& p3, const Vec3& p4);
/// The same angle signed by the way n2 turns from n1 about the edge p2 - p1, in
/// (-pi, pi]: |signed_normal_angle| = normal_angle.
double signed_normal_angle(const Vec3& p1, const Vec3& p2, const Vec3& p3, const Vec3& p4);
/// Gradient of the signed angle with respect to p1..p4 (smooth through 0).
bool signed_angle_gradient(const Vec3& p1, const Vec3& p2, const Vec3& p3, const Vec3& p4, Vec3 grad[4]);

/// Which angle the bending constraint keeps: the paper's eq. (19),
/// C = arccos(n1 . n2) - phi0 = |theta| - |theta0|, whose gradient flips sign
/// where the pair passes through flat (theta = 0: a kink that a rest-curved pair
/// driven through flat oscillates across); or the signed C = theta - theta0,
/// smooth there (beyond the paper).
enum class BendingAngle { Unsigned, Signed };
/// Gradients of C with respect to p1..p4 (eqs. 22-25 in value). Computed with
/// Bridson et al.'s bounded form of the dihedral-angle gradient instead of the
/// 1/sqrt(1 - d^2) form, which is 0/0 when the triangles are coplanar.
/// Returns false (zero gradients) for a degenerate configuration.
bool bending_gradient(const Vec3& p1, const Vec3& p2, const Vec3& p3, const Vec3& p4, Vec3 grad[4]);
/// Projection: dp_i = -s w_i C / (sum_j w_j |grad_j C|^2) grad_i C (eq. 13 with
/// masses; the paper's eq. (26) with its extra factor 4 is Mueller 2007's
/// typo, not used). rest_angle is the signed rest angle theta0 (signed_normal_angle
/// at rest). Returns false with zero corrections when nothing moves.
inline bool project_bending(const Vec3& p1, double w1, const Vec3& p2, double w2, const Vec3& p3, double w3,
                            const Vec3& p4, double w4, double rest_angle, double stiffness, Vec3 corr[4],
                            BendingAngle kind = BendingAngle::Unsigned);

/// Mueller et al. 2007's iteration-count correction: the per-iteration stiffness
/// k' = 1 - (1 - k)^(1/n) so that n iterations act like stiffness k once.
double stiffness_per_iteration(double stiffness, int iterations);

// ---------------------------------------------------------------------------
// The kernels of the projection loop, inline so that the solver's sweep compiles
// them into its loop body (as out-of-line calls they cost twice as much).

// GCC does not inline these on its own (too large), and as calls they cost a
// third of the sweep.
#define TB_PBD_INLINE inline __attribute__((always_inline))

namespace detail {
constexpr double kTiny = 1e-30;

/// Signed angle theta between the wing normals, turning about the edge p2 - p1,
/// and (if grad) its gradient; |theta| = arccos(n1 . n2). The normals are
/// Bridson's N1 = (p3 - p1) x (p3 - p2), N2 = (p4 - p2) x (p4 - p1): consistently
/// oriented, so that they coincide when the two triangles are coplanar and
/// unfolded, and the same arithmetic at rest and in a frame, so the rest angle and
/// the angle at rest are bitwise equal (zero load leaves the surface exactly at
/// rest). The angle is atan2(sin, cos): accurate near 0 and pi, where arccos
/// loses half the digits, and never NaN (the paper's arccos argument clamped,
/// exactly). The gradient is Bridson, Marino, Fedkiw 2003 (as in Bender's
/// solve_DihedralConstraint): with e = p2 - p1 and m3 = n1 / |n1|^2,
/// m4 = n2 / |n2|^2, d theta/d p3 = |e| m3, d theta/d p4 = |e| m4 and for p1, p2
/// the combinations of the wings' projections on e below; bounded as the
/// triangles become coplanar (the 1/sqrt(1 - d^2) of eqs. 22-24 is 0/0 there).
/// Signs checked against finite differences in tests/models/pbd/constraints_test.cc.
/// Returns false (theta = 0, grad untouched) for a degenerate configuration.
TB_PBD_INLINE bool signed_angle(const Vec3& p1, const Vec3& p2, const Vec3& p3, const Vec3& p4, double& theta,
                                Vec3* grad) {
  theta = 0;
  const Vec3 e = p2 - p1;
  const double elen = e.norm();
  const Vec3 n1 = (p3 - p1).cross(p3 - p2), n2 = (p4 - p2).cross(p4 - p1);
  const double a3 = n1.squaredNorm(), a4 = n2.squaredNorm();
  if (elen <= kTiny || a3 <= kTiny || a4 <= kTiny) return false;
  // Reciprocals once, then products: divisions are the slowest links of the
  // dependency chain of a projection.
  const double inv = 1.0 / elen;
  theta = std::atan2(-n1.cross(n2).dot(e) * inv, n1.dot(n2));
  if (!grad) return true;
  const Vec3 m3 = n1 * (1.0 / a3), m4 = n2 * (1.0 / a4);
  grad[0] = (p3 - p2).dot(e) * inv * m3 + (p4 - p2).dot(e) * inv * m4;
  grad[1] = -((p3 - p1).dot(e) * inv * m3 + (p4 - p1).dot(e) * inv * m4);
  grad[2] = elen * m3;
  grad[3] = elen * m4;
  return true;
}
}  // namespace detail

TB_PBD_INLINE bool project_stretch(const Vec3& p1, double w1, const Vec3& p2, double w2, double rest_length,
                                   double stiffness, Vec3& corr1, Vec3& corr2) {
  const double wsum = w1 + w2;
  const Vec3 d = p1 - p2;
  const double len = d.norm();
  if (wsum <= 0 || len <= detail::kTiny) {
    corr1.setZero();
    corr2.setZero();
    return false;
  }
  const Vec3 n = d * (1.0 / len);
  const double s = stiffness * (len - rest_length) / wsum;
  corr1 = (-s * w1) * n;  // eq. (17)
  corr2 = (s * w2) * n;   // eq. (18)
  return true;
}

TB_PBD_INLINE bool project_bending(const Vec3& p1, double w1, const Vec3& p2, double w2, const Vec3& p3, double w3,
                                   const Vec3& p4, double w4, double rest_angle, double stiffness, Vec3 corr[4],
                                   BendingAngle kind) {
  double theta = 0;
  if (!detail::signed_angle(p1, p2, p3, p4, theta, corr)) {  // corr holds the gradient of theta
    for (int k = 0; k < 4; ++k) corr[k].setZero();
    return false;
  }
  double c = theta - rest_angle;
  double sign = 1;
  if (kind == BendingAngle::Unsigned) {  // eq. (19): C = |theta| - |theta_0|, grad C = sign(theta) grad theta
    sign = theta < 0 ? -1.0 : 1.0;
    c = std::abs(theta) - std::abs(rest_angle);
  }
  const double w[4] = {w1, w2, w3, w4};
  double denom = 0;
  for (int k = 0; k < 4; ++k) denom += w[k] * corr[k].squaredNorm();  // |sign g|^2 = |g|^2
  if (denom <= detail::kTiny) {
    for (int k = 0; k < 4; ++k) corr[k].setZero();
    return false;
  }
  const double s = -stiffness * c / denom;
  for (int k = 0; k < 4; ++k) corr[k] = s * w[k] * (sign * corr[k]);
  return true;
}

}  // namespace tb::pbd
