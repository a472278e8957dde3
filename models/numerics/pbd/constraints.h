// PBD constraint functions, gradients and projections (paper 1.4) as stateless
// functions of one constraint, after Bender's PositionBasedDynamics
// (github.com/InteractiveComputerGraphics/PositionBasedDynamics).
// Each projection returns position corrections; the caller applies them. They
// wrap the kernels of projection_kernels.h, which the solver runs on batches.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

namespace tb::pbd {

using Vec3 = Eigen::Vector3d;

/// Lengths, squared normal lengths and projection denominators at or below this
/// count as degenerate: the constraint then moves nothing (kernels and reference alike).
constexpr double kTiny = 1e-30;
/// A bending projection's denominator sum_j w_j |grad_j C|^2 at or below this
/// fraction of (sum_j w_j) max_j |grad_j C|^2 is rounding noise: the free vertices
/// cannot change the angle to first order (a free hinge end whose wings' feet both
/// lie at the other end), and C / |grad C| would be noise over noise.
constexpr double kNoiseGradient = 1e-20;
/// The same for a sweep in single precision, whose rounding noise is about
/// (6e-8)^2 = 4e-15 of that scale: 1e-10 lies well above it and below any
/// gradient ratio (1e-5) that matters.
constexpr double kNoiseGradientSingle = 1e-10;

// The bending step's trust region (kernels and reference alike): a bending
// projection whose longest step |dp_i| exceeds q |p2 - p1| is shortened to that
// length (all dp_i scaled alike, so its direction stays), where
// q^2 = sum_j w_j |grad_j C|^2 / ((sum_j w_j) max_j |grad_j C|^2) in (0, 1] is the
// share of the constraint's gradient that its free vertices hold (the ratio
// kNoiseGradient bounds below). The angle's second derivatives scale as
// max |grad C| / |p2 - p1|, so eq. (13)'s linear step along a gradient of q times
// that size holds over about q |p2 - p1|, no further. A regular step (q ~ 0.5-1,
// |C| below about 1 rad) is untouched; the limit stops a free hinge end whose
// gradient nearly vanishes (q = 1e-7 to 1e-4 on an L-block whose support follows
// the coarse FEM: steps of 7 to 80 mm across a 6.7 mm hinge crumpled its surface).

/// Which angle the bending constraint keeps: the paper's eq. (19),
/// C = arccos(n1 . n2) - phi0 = |theta| - |theta0|, whose gradient flips sign
/// where the pair passes through flat (theta = 0: a kink that a rest-curved pair
/// driven through flat oscillates across); or the signed C = theta - theta0,
/// smooth there (beyond the paper).
enum class BendingAngle { Unsigned, Signed };

/// Stretch constraint, eq. (14): C = |p1 - p2| - rest_length.
double stretch_constraint(const Vec3& p1, const Vec3& p2, double rest_length);
/// Its gradients, eqs. (15)-(16). Zero when p1 == p2.
void stretch_gradient(const Vec3& p1, const Vec3& p2, Vec3& grad1, Vec3& grad2);
/// Projection, eqs. (17)-(18), scaled by stiffness in [0, 1]. Returns false (and
/// zero corrections) when both points are fixed or coincide.
bool project_stretch(const Vec3& p1, double w1, const Vec3& p2, double w2, double rest_length, double stiffness,
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

/// Gradients of C with respect to p1..p4 (eqs. 22-25 in value). Computed with
/// Bridson et al.'s bounded form of the dihedral-angle gradient instead of the
/// 1/sqrt(1 - d^2) form, which is 0/0 when the triangles are coplanar.
/// Returns false (zero gradients) for a degenerate configuration.
bool bending_gradient(const Vec3& p1, const Vec3& p2, const Vec3& p3, const Vec3& p4, Vec3 grad[4]);
/// Projection: dp_i = -s w_i C / (sum_j w_j |grad_j C|^2) grad_i C (eq. 13 with
/// masses; the paper's eq. (26) with its extra factor 4 is Mueller 2007's
/// typo, not used). rest_angle is the signed rest angle theta0 (signed_normal_angle
/// at rest). Returns false with zero corrections when nothing moves.
bool project_bending(const Vec3& p1, double w1, const Vec3& p2, double w2, const Vec3& p3, double w3, const Vec3& p4,
                     double w4, double rest_angle, double stiffness, Vec3 corr[4],
                     BendingAngle kind = BendingAngle::Unsigned);

/// Mueller et al. 2007's iteration-count correction: the per-iteration stiffness
/// k' = 1 - (1 - k)^(1/n) so that n iterations act like stiffness k once.
double stiffness_per_iteration(double stiffness, int iterations);

}  // namespace tb::pbd
