// A scalar reference implementation of every PBD projection (paper 1.4), written
// straight from the equations with Eigen, one constraint at a time. It shares no
// arithmetic with the SIMD kernels of projection_kernels.h (unit normals and
// std::atan2 here, unnormalised normals and a Cephes atan2 there; the gradient in
// its textbook form), so tests/models/numerics/pbd/reference_projections_test.cc can hold
// the kernels to it, and a new constraint type can start from here. The solver
// runs it when asked ("kernels": "reference").
#pragma once

#include "constraints.h"

namespace tb::pbd::reference {

/// Stretch projection, eqs. (14)-(18), scaled by stiffness k in [0, 1]:
/// C = |p1 - p2| - l (14), grad_p1 C = (p1 - p2) / |p1 - p2| = -grad_p2 C (15, 16),
/// dp1 = -k w1 / (w1 + w2) C grad_p1 C (17), dp2 = -k w2 / (w1 + w2) C grad_p2 C (18).
/// False (zero corrections) when w1 + w2 = 0 or |p1 - p2| <= kTiny.
bool project_stretch(const Vec3& p1, double w1, const Vec3& p2, double w2, double rest_length, double stiffness,
                     Vec3& corr1, Vec3& corr2);

/// The dihedral angle of the bending constraint as the code defines it (see
/// constraints.h): triangles (p1, p2, p3) and (p2, p1, p4) sharing e = p2 - p1,
/// with the normals of eqs. (20)-(21), n2 oriented consistently with n1 (flat and
/// unfolded: n1 = n2), theta = atan2(-(n1 x n2) . e / |e|, n1 . n2) in (-pi, pi],
/// so |theta| = arccos(n1 . n2), eq. (19). `grad` (if not null) gets d theta / d p_i
/// in Bridson, Marino, Fedkiw 2003's bounded form (the value of eqs. 22-25 where
/// those are defined). False (theta = 0, zero gradient) when |e|, |N1|^2 or
/// |N2|^2 (unnormalised normals) is <= kTiny.
bool dihedral_angle(const Vec3& p1, const Vec3& p2, const Vec3& p3, const Vec3& p4, double& theta, Vec3 grad[4]);

/// The gradient of arccos(n1 . n2) = |theta| exactly as eqs. (22)-(25) print it,
/// -(1 / sqrt(1 - d^2)) (dn1/dp_i)^T n2 + ..., with d = n1 . n2 and the unit
/// normals' Jacobians (I - n n^T) / |N| dN/dp_i. Singular where the pair is flat
/// (d = 1) or folded (d = -1): a check of the bounded form away from there, not
/// used by the projection. False when degenerate or |d| >= 1.
bool paper_arccos_gradient(const Vec3& p1, const Vec3& p2, const Vec3& p3, const Vec3& p4, Vec3 grad[4]);

/// Bending projection: C = |theta| - |theta0| (eq. 19, kind Unsigned; gradient
/// sign(theta) grad theta, sign(0) = 1) or C = theta - theta0 (Signed), and
/// dp_i = -k w_i C grad_i C / (sum_j w_j |grad_j C|^2) (eq. 13 with masses; the
/// paper's eq. 26 with its factor 4 is not used). rest_angle is the signed rest
/// angle theta0. False (zero corrections) when the angle is degenerate, the
/// denominator is <= kTiny or <= kNoiseGradient (sum_j w_j) max_j |grad_j C|^2. A step
/// beyond its trust region (constraints.h) is shortened to reach its edge.
bool project_bending(const Vec3& p1, double w1, const Vec3& p2, double w2, const Vec3& p3, double w3, const Vec3& p4,
                     double w4, double rest_angle, double stiffness, Vec3 corr[4], BendingAngle kind);

/// XPBD (Macklin, Mueller, Chentanez 2016) updates of one constraint with
/// compliance alpha (xpbd_compliance.h) and time step dt, alpha~ = alpha / dt^2
/// (their eq. 4), and the constraint's Lagrange multiplier `lambda` accumulated
/// over the frame's iterations (0 at the frame's start):
///   dlambda = (-C - alpha~ lambda) / (sum_j w_j |grad_j C|^2 + alpha~)   (their eq. 18)
///   dp_i = w_i grad_i C dlambda                                          (their eq. 17)
/// and lambda += dlambda. C and grad C are the stretch constraint's (eqs. 14-16,
/// |grad C| = 1) or the bending constraint's as `kind` says (project_bending).
/// With alpha~ = 0 and lambda = 0 a step equals the PBD projection with stiffness 1.
/// False (zero corrections, lambda unchanged) where the PBD projection moves nothing.
bool xpbd_stretch(const Vec3& p1, double w1, const Vec3& p2, double w2, double rest_length, double alpha_tilde,
                  double& lambda, Vec3& corr1, Vec3& corr2);
bool xpbd_bending(const Vec3& p1, double w1, const Vec3& p2, double w2, const Vec3& p3, double w3, const Vec3& p4,
                  double w4, double rest_angle, double alpha_tilde, double& lambda, Vec3 corr[4], BendingAngle kind);

}  // namespace tb::pbd::reference
