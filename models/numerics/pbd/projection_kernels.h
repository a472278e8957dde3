// The constraint projections of paper 1.4 as kernels over one constraint (T =
// double or float) or a batch of independent constraints, one per lane (T = a
// lanes::Vector or Twin).
// constraints.h wraps them for single constraints; the solver's sweep runs them
// on batches. Branch-free: a lane that cannot move (degenerate or fixed) gets zero
// corrections and a false mask entry.
#pragma once

#include "constraints.h"
#include "lane_math.h"

namespace tb::pbd::kernels {

using lanes::Triple;

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
/// Signs checked against finite differences in tests/models/numerics/pbd/constraints_test.cc.
/// Returns the mask of non-degenerate lanes; degenerate ones get theta = 0 and a
/// finite gradient the caller must ignore. `hinge2` (if not null) gets |e|^2.
template <class T>
TB_PBD_INLINE auto signed_angle(const Triple<T> p[4], T& theta, Triple<T>* grad, T* hinge2 = nullptr) {
  using lanes::splat;
  const T one = splat<T>(1), tiny = splat<T>(kTiny);
  const Triple<T> e = p[1] - p[0];
  const T ee = dot(e, e), elen = lanes::sqrt(ee);
  if (hinge2) *hinge2 = ee;
  const Triple<T> n1 = cross(p[2] - p[0], p[2] - p[1]), n2 = cross(p[3] - p[1], p[3] - p[0]);
  const T a3 = dot(n1, n1), a4 = dot(n2, n2);
  const auto ok = (elen > tiny) & (a3 > tiny) & (a4 > tiny);
  // atan2(sin, cos) with both scaled by |n1| |n2| |e| (the angle does not change):
  // no division before atan2 on the longest dependency chain of a projection.
  theta = lanes::select(ok, lanes::atan2(-dot(cross(n1, n2), e), dot(n1, n2) * elen), T{});
  if (grad) {
    // With m3' = m3 / |e| and m4' = m4 / |e| (1/|e|, 1/a3 and 1/a4 from one
    // division, guarded so degenerate lanes stay finite) and the wings' projections
    // on e, d3 = (p3 - p1) . e, d4 = (p4 - p1) . e (and (p3 - p2) . e = d3 - |e|^2,
    // likewise for p4):
    const T r34 = one / lanes::select(ok, elen * (a3 * a4), one);
    const Triple<T> m3 = (a4 * r34) * n1, m4 = (a3 * r34) * n2;
    const T d3 = dot(p[2] - p[0], e), d4 = dot(p[3] - p[0], e);
    grad[0] = (d3 - ee) * m3 + (d4 - ee) * m4;
    grad[1] = (-d3) * m3 + (-d4) * m4;
    grad[2] = ee * m3;
    grad[3] = ee * m4;
  }
  return ok;
}

/// The inverse-mass shares w1 / (w1 + w2) and w2 / (w1 + w2) of a stretch
/// constraint's correction (0 when both points are fixed); constant per constraint.
template <class S>
inline void stretch_shares(S w1, S w2, S& share1, S& share2) {
  const S wsum = w1 + w2;
  share1 = wsum > 0 ? w1 / wsum : 0;
  share2 = wsum > 0 ? w2 / wsum : 0;
}

/// Stretch projection, eqs. (14)-(18), scaled by stiffness in [0, 1]: with
/// s = k (|d| - rest) / |d| and d = p1 - p2, dp1 = -s share1 d and dp2 = s share2 d
/// (shares from stretch_shares). The mask is false (zero corrections) where both
/// points are fixed or coincide.
template <class T>
TB_PBD_INLINE auto project_stretch(const Triple<T>& p1, T share1, const Triple<T>& p2, T share2, T rest_length,
                                   double stiffness, Triple<T>& corr1, Triple<T>& corr2) {
  const T one = lanes::splat<T>(1);
  const Triple<T> d = p1 - p2;
  const T len = lanes::sqrt(dot(d, d));
  const auto ok = (share1 + share2 > T{}) & (len > lanes::splat<T>(kTiny));
  const T inv_len = one / lanes::select(ok, len, one);  // starts while len - rest is computed
  const T s = lanes::select(ok, lanes::splat<T>(stiffness) * (len - rest_length) * inv_len, T{});
  corr1 = (-s * share1) * d;  // eq. (17)
  corr2 = (s * share2) * d;   // eq. (18)
  return ok;
}

/// Bending projection: dp_i = -s w_i C / (sum_j w_j |grad_j C|^2) grad_i C (eq. 13
/// with masses; the paper's eq. (26) with its extra factor 4 is Mueller 2007's
/// typo, not used), C as `kind` says (constraints.h). rest_angle is the signed
/// rest angle theta0. The mask is false (zero corrections) where nothing moves:
/// degenerate, or the denominator at or below kTiny or kNoiseGradient of its scale.
/// A step beyond its trust region (constraints.h) is shortened to reach its edge.
template <class T>
TB_PBD_INLINE auto project_bending(const Triple<T> p[4], const T w[4], T rest_angle, double stiffness,
                                   BendingAngle kind, Triple<T> corr[4]) {
  T theta, hinge2;
  auto ok = signed_angle(p, theta, corr, &hinge2);  // corr holds the gradient of theta
  T c = theta - rest_angle;
  T sign = lanes::splat<T>(1);
  if (kind == BendingAngle::Unsigned) {  // eq. (19): C = |theta| - |theta_0|, grad C = sign(theta) grad theta
    sign = lanes::select(theta < T{}, lanes::splat<T>(-1), sign);
    c = lanes::abs(theta) - lanes::abs(rest_angle);
  }
  T denom{}, largest{}, widest{};  // widest: max_k w_k^2 |g_k|^2 = (longest step / s)^2
  for (int k = 0; k < 4; ++k) {
    const T g2 = dot(corr[k], corr[k]);  // |sign g|^2 = |g|^2
    const T wg2 = w[k] * g2;
    denom += wg2;
    largest = lanes::select(g2 > largest, g2, largest);
    widest = lanes::select(w[k] * wg2 > widest, w[k] * wg2, widest);
  }
  const T scale = (w[0] + w[1] + w[2] + w[3]) * largest;  // denom / scale = q^2 in (0, 1]
  ok = ok & (denom > lanes::splat<T>(kTiny)) &
       (denom >
        lanes::splat<T>(std::is_same_v<lanes::Element<T>, float> ? kNoiseGradientSingle : kNoiseGradient) * scale);
  // The reciprocal of denom does not wait for the angle (c): off the critical path.
  const T inv_denom = lanes::splat<T>(1) / lanes::select(ok, denom, lanes::splat<T>(1));
  T s = lanes::select(ok, lanes::splat<T>(-stiffness) * c * inv_denom, T{});
  // The trust region (constraints.h): the longest step s sqrt(widest) at most
  // q |e|, q^2 = denom / scale; beyond, s shrinks to reach it.
  const T reach = hinge2 * denom, step = s * s * widest * scale;
  const auto beyond = step > reach;
  if (lanes::any(beyond))  // rare: a branch, not a square root and a division on every projection
    s = lanes::select(beyond, s * lanes::sqrt(reach / lanes::select(beyond, step, lanes::splat<T>(1))), s);
  s = s * sign;
  for (int k = 0; k < 4; ++k) corr[k] = (s * w[k]) * corr[k];
  return ok;
}

}  // namespace tb::pbd::kernels
