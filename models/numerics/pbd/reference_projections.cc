#include "reference_projections.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace tb::pbd::reference {
namespace {

using Mat3 = Eigen::Matrix3d;

/// [a]_x, the matrix with [a]_x b = a x b.
Mat3 skew(const Vec3& a) {
  Mat3 m;
  m << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
  return m;
}

/// The unnormalised normals of eqs. (20) and (21), the second turned to face the
/// same way as the first: N1 = (p2 - p1) x (p3 - p1), N2 = -(p2 - p1) x (p4 - p1).
void normals(const Vec3& p1, const Vec3& p2, const Vec3& p3, const Vec3& p4, Vec3& N1, Vec3& N2) {
  N1 = (p2 - p1).cross(p3 - p1);
  N2 = -(p2 - p1).cross(p4 - p1);
}

bool degenerate(const Vec3& e, const Vec3& N1, const Vec3& N2) {
  return !(e.norm() > kTiny) || !(N1.squaredNorm() > kTiny) || !(N2.squaredNorm() > kTiny);
}

}  // namespace

bool project_stretch(const Vec3& p1, double w1, const Vec3& p2, double w2, double rest_length, double stiffness,
                     Vec3& corr1, Vec3& corr2) {
  corr1.setZero();
  corr2.setZero();
  const Vec3 d = p1 - p2;
  const double length = d.norm();
  if (!(w1 + w2 > 0) || !(length > kTiny)) return false;
  const double C = length - rest_length;              // eq. (14)
  const Vec3 grad1 = d / length;                      // eq. (15); eq. (16) is its negative
  corr1 = -stiffness * (w1 / (w1 + w2)) * C * grad1;  // eq. (17)
  corr2 = stiffness * (w2 / (w1 + w2)) * C * grad1;   // eq. (18)
  return true;
}

bool dihedral_angle(const Vec3& p1, const Vec3& p2, const Vec3& p3, const Vec3& p4, double& theta, Vec3 grad[4]) {
  theta = 0;
  if (grad)
    for (int i = 0; i < 4; ++i) grad[i].setZero();
  const Vec3 e = p2 - p1;
  Vec3 N1, N2;
  normals(p1, p2, p3, p4, N1, N2);
  if (degenerate(e, N1, N2)) return false;
  const Vec3 n1 = N1.normalized(), n2 = N2.normalized(), e_unit = e.normalized();  // eqs. (20), (21)
  theta = std::atan2(-n1.cross(n2).dot(e_unit), n1.dot(n2));                       // eq. (19): |theta| = arccos(n1.n2)
  if (grad) {
    // Bridson et al. 2003: the wings move along their normals by |e| / |N|^2 (the
    // inverse height over e), the edge's ends by the wings' heights weighted by
    // where the wings' feet lie along e.
    const Vec3 m1 = N1 / N1.squaredNorm(), m2 = N2 / N2.squaredNorm();
    grad[2] = e.norm() * m1;
    grad[3] = e.norm() * m2;
    grad[0] = (p3 - p2).dot(e_unit) * m1 + (p4 - p2).dot(e_unit) * m2;
    grad[1] = -(p3 - p1).dot(e_unit) * m1 - (p4 - p1).dot(e_unit) * m2;
  }
  return true;
}

bool paper_arccos_gradient(const Vec3& p1, const Vec3& p2, const Vec3& p3, const Vec3& p4, Vec3 grad[4]) {
  for (int i = 0; i < 4; ++i) grad[i].setZero();
  const Vec3 e = p2 - p1;
  Vec3 N1, N2;
  normals(p1, p2, p3, p4, N1, N2);
  if (degenerate(e, N1, N2)) return false;
  const Vec3 n1 = N1.normalized(), n2 = N2.normalized();
  const double d = n1.dot(n2);
  if (!(std::abs(d) < 1)) return false;
  // dn/dp = (I - n n^T) / |N| dN/dp, with dN1/dp2 = -[p3 - p1]_x, dN1/dp3 = [p2 - p1]_x,
  // dN2/dp2 = [p4 - p1]_x, dN2/dp4 = -[p2 - p1]_x.
  const Mat3 P1 = (Mat3::Identity() - n1 * n1.transpose()) / N1.norm();
  const Mat3 P2 = (Mat3::Identity() - n2 * n2.transpose()) / N2.norm();
  const Mat3 dn1_dp2 = P1 * -skew(p3 - p1), dn1_dp3 = P1 * skew(e);
  const Mat3 dn2_dp2 = P2 * skew(p4 - p1), dn2_dp4 = P2 * -skew(e);
  const double f = -1 / std::sqrt(1 - d * d);
  grad[2] = f * (dn1_dp3.transpose() * n2);                             // eq. (22)
  grad[3] = f * (dn2_dp4.transpose() * n1);                             // eq. (23)
  grad[1] = f * (dn1_dp2.transpose() * n2 + dn2_dp2.transpose() * n1);  // eq. (24)
  grad[0] = -grad[1] - grad[2] - grad[3];                               // eq. (25)
  return true;
}

namespace {

/// The bending constraint's value C, gradients grad C and denominator
/// sum_j w_j |grad_j C|^2 as project_bending describes them; false when nothing
/// can move (degenerate angle, or a denominator at or below kTiny or kNoiseGradient
/// of its scale).
bool bending_terms(const Vec3 p[4], const double w[4], double rest_angle, BendingAngle kind, double& C, Vec3 grad[4],
                   double& denominator) {
  double theta;
  if (!dihedral_angle(p[0], p[1], p[2], p[3], theta, grad)) return false;
  C = theta - rest_angle;
  if (kind == BendingAngle::Unsigned) {  // eq. (19): C = |theta| - |theta0|, grad |theta| = sign(theta) grad theta
    C = std::abs(theta) - std::abs(rest_angle);
    if (theta < 0)
      for (int i = 0; i < 4; ++i) grad[i] = -grad[i];
  }
  denominator = 0;
  double largest = 0;
  for (int i = 0; i < 4; ++i) {
    denominator += w[i] * grad[i].squaredNorm();
    largest = std::max(largest, grad[i].squaredNorm());
  }
  return denominator > kTiny && denominator > kNoiseGradient * (w[0] + w[1] + w[2] + w[3]) * largest;
}

/// The factor in (0, 1] that shortens the bending corrections `corr` of the
/// constraint on p to its trust region (constraints.h): max_i |corr_i| at most
/// q |p2 - p1|, with q^2 = denominator / ((sum_j w_j) max_j |grad_j C|^2).
double trust_region_factor(const Vec3 p[4], const double w[4], const Vec3 grad[4], double denominator,
                           const Vec3 corr[4]) {
  double longest = 0, largest = 0;
  for (int i = 0; i < 4; ++i) {
    longest = std::max(longest, corr[i].squaredNorm());
    largest = std::max(largest, grad[i].squaredNorm());
  }
  const double step = longest * ((w[0] + w[1] + w[2] + w[3]) * largest);
  const double reach = (p[1] - p[0]).squaredNorm() * denominator;
  return step > reach ? std::sqrt(reach / step) : 1.0;
}

}  // namespace

bool project_bending(const Vec3& p1, double w1, const Vec3& p2, double w2, const Vec3& p3, double w3, const Vec3& p4,
                     double w4, double rest_angle, double stiffness, Vec3 corr[4], BendingAngle kind) {
  for (int i = 0; i < 4; ++i) corr[i].setZero();
  const Vec3 p[4] = {p1, p2, p3, p4};
  const double w[4] = {w1, w2, w3, w4};
  double C, denominator;
  Vec3 grad[4];
  if (!bending_terms(p, w, rest_angle, kind, C, grad, denominator)) return false;
  for (int i = 0; i < 4; ++i) corr[i] = (-stiffness * C * w[i] / denominator) * grad[i];  // eq. (13) with masses
  const double shorten = trust_region_factor(p, w, grad, denominator, corr);
  for (int i = 0; i < 4; ++i) corr[i] *= shorten;
  return true;
}

bool xpbd_stretch(const Vec3& p1, double w1, const Vec3& p2, double w2, double rest_length, double alpha_tilde,
                  double& lambda, Vec3& corr1, Vec3& corr2) {
  corr1.setZero();
  corr2.setZero();
  const Vec3 d = p1 - p2;
  const double length = d.norm();
  if (!(w1 + w2 > 0) || !(length > kTiny)) return false;
  const double C = length - rest_length;  // eq. (14)
  const Vec3 grad1 = d / length;          // eq. (15), |grad1| = 1; eq. (16) is its negative
  const double dlambda = (-C - alpha_tilde * lambda) / (w1 + w2 + alpha_tilde);  // XPBD eq. (18)
  lambda += dlambda;
  corr1 = (w1 * dlambda) * grad1;  // XPBD eq. (17): dp_i = w_i grad_i C dlambda
  corr2 = (-w2 * dlambda) * grad1;
  return true;
}

bool xpbd_bending(const Vec3& p1, double w1, const Vec3& p2, double w2, const Vec3& p3, double w3, const Vec3& p4,
                  double w4, double rest_angle, double alpha_tilde, double& lambda, Vec3 corr[4], BendingAngle kind) {
  for (int i = 0; i < 4; ++i) corr[i].setZero();
  const Vec3 p[4] = {p1, p2, p3, p4};
  const double w[4] = {w1, w2, w3, w4};
  double C, denominator;
  Vec3 grad[4];
  if (!bending_terms(p, w, rest_angle, kind, C, grad, denominator)) return false;
  double dlambda = (-C - alpha_tilde * lambda) / (denominator + alpha_tilde);  // XPBD eq. (18)
  for (int i = 0; i < 4; ++i) corr[i] = (w[i] * dlambda) * grad[i];            // XPBD eq. (17)
  const double shorten = trust_region_factor(p, w, grad, denominator, corr);
  dlambda *= shorten;
  for (int i = 0; i < 4; ++i) corr[i] *= shorten;
  lambda += dlambda;
  return true;
}

}  // namespace tb::pbd::reference
