#include "constraints.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace tb::pbd {
namespace {
constexpr double kTiny = 1e-30;
}

double stretch_constraint(const Vec3& p1, const Vec3& p2, double rest_length) { return (p1 - p2).norm() - rest_length; }

void stretch_gradient(const Vec3& p1, const Vec3& p2, Vec3& g1, Vec3& g2) {
  const Vec3 d = p1 - p2;
  const double len = d.norm();
  g1 = len > kTiny ? Vec3(d / len) : Vec3::Zero();
  g2 = -g1;
}

bool project_stretch(const Vec3& p1, double w1, const Vec3& p2, double w2, double rest_length, double stiffness,
                     Vec3& corr1, Vec3& corr2) {
  corr1.setZero();
  corr2.setZero();
  const double wsum = w1 + w2;
  const Vec3 d = p1 - p2;
  const double len = d.norm();
  if (wsum <= 0 || len <= kTiny) return false;
  const Vec3 n = d / len;
  const double c = len - rest_length;
  corr1 = -stiffness * w1 / wsum * c * n;  // eq. (17)
  corr2 = stiffness * w2 / wsum * c * n;   // eq. (18)
  return true;
}

namespace {
/// Normals (unnormalised) of triangles (p1, p2, p3) and (p2, p1, p4): consistently
/// oriented, so that they coincide when the two triangles are coplanar and
/// unfolded. Written as Bridson's N1 = (p3 - p1) x (p3 - p2), N2 = (p4 - p2) x
/// (p4 - p1), the same arithmetic the gradient uses, so the rest angle and the
/// angle at rest are bitwise equal (zero load leaves the surface exactly at rest).
void wing_normals(const Vec3& p1, const Vec3& p2, const Vec3& p3, const Vec3& p4, Vec3& n1, Vec3& n2) {
  n1 = (p3 - p1).cross(p3 - p2);
  n2 = (p4 - p2).cross(p4 - p1);
}

/// Signed angle theta between the wing normals, turning about the edge p2 - p1,
/// and (if grad) its gradient; |theta| = arccos(n1 . n2). The angle is
/// atan2(sin, cos): accurate near 0 and pi, where arccos loses half the digits,
/// and never NaN (the paper's arccos argument clamped, exactly). The gradient is
/// Bridson, Marino, Fedkiw 2003 (as in Bender's solve_DihedralConstraint): with
/// e = p2 - p1 and m3 = n1 / |n1|^2, m4 = n2 / |n2|^2, d theta/d p3 = |e| m3,
/// d theta/d p4 = |e| m4 and for p1, p2 the combinations of the wings'
/// projections on e below; bounded as the triangles become coplanar (the
/// 1/sqrt(1 - d^2) of eqs. 22-24 is 0/0 there). Signs checked against finite
/// differences in tests/models/pbd/constraints_test.cc.
/// Returns false (theta = 0, zero gradient) for a degenerate configuration.
bool signed_angle(const Vec3& p1, const Vec3& p2, const Vec3& p3, const Vec3& p4, double& theta, Vec3* grad) {
  theta = 0;
  if (grad)
    for (int k = 0; k < 4; ++k) grad[k].setZero();
  const Vec3 e = p2 - p1;
  const double elen = e.norm();
  Vec3 n1, n2;
  wing_normals(p1, p2, p3, p4, n1, n2);
  const double a3 = n1.squaredNorm(), a4 = n2.squaredNorm();
  if (elen <= kTiny || a3 <= kTiny || a4 <= kTiny) return false;
  theta = std::atan2(-n1.cross(n2).dot(e) / elen, n1.dot(n2));
  if (!grad) return true;
  const Vec3 m3 = n1 / a3, m4 = n2 / a4;
  const double inv = 1.0 / elen;
  grad[0] = (p3 - p2).dot(e) * inv * m3 + (p4 - p2).dot(e) * inv * m4;
  grad[1] = -((p3 - p1).dot(e) * inv * m3 + (p4 - p1).dot(e) * inv * m4);
  grad[2] = elen * m3;
  grad[3] = elen * m4;
  return true;
}
}  // namespace

double normal_angle(const Vec3& p1, const Vec3& p2, const Vec3& p3, const Vec3& p4) {
  return std::abs(signed_normal_angle(p1, p2, p3, p4));
}

double signed_normal_angle(const Vec3& p1, const Vec3& p2, const Vec3& p3, const Vec3& p4) {
  double theta = 0;
  signed_angle(p1, p2, p3, p4, theta, nullptr);
  return theta;
}

double bending_constraint(const Vec3& p1, const Vec3& p2, const Vec3& p3, const Vec3& p4, double rest_angle) {
  double theta = 0;
  if (!signed_angle(p1, p2, p3, p4, theta, nullptr)) return 0;
  return std::abs(theta) - rest_angle;
}

bool bending_gradient(const Vec3& p1, const Vec3& p2, const Vec3& p3, const Vec3& p4, Vec3 g[4]) {
  double theta = 0;
  if (!signed_angle(p1, p2, p3, p4, theta, g)) return false;
  const double sign = theta < 0 ? -1.0 : 1.0;  // grad |theta| = sign(theta) grad theta
  for (int k = 0; k < 4; ++k) g[k] *= sign;
  return true;
}

bool signed_angle_gradient(const Vec3& p1, const Vec3& p2, const Vec3& p3, const Vec3& p4, Vec3 g[4]) {
  double theta = 0;
  return signed_angle(p1, p2, p3, p4, theta, g);
}

bool project_bending(const Vec3& p1, double w1, const Vec3& p2, double w2, const Vec3& p3, double w3, const Vec3& p4,
                     double w4, double rest_angle, double stiffness, Vec3 corr[4], BendingAngle kind) {
  Vec3 g[4];
  double theta = 0;
  for (int k = 0; k < 4; ++k) corr[k].setZero();
  if (!signed_angle(p1, p2, p3, p4, theta, g)) return false;
  double c = theta - rest_angle;
  if (kind == BendingAngle::Unsigned) {  // eq. (19): C = |theta| - |theta_0|
    const double sign = theta < 0 ? -1.0 : 1.0;
    for (int k = 0; k < 4; ++k) g[k] *= sign;
    c = std::abs(theta) - std::abs(rest_angle);
  }
  const double w[4] = {w1, w2, w3, w4};
  double denom = 0;
  for (int k = 0; k < 4; ++k) denom += w[k] * g[k].squaredNorm();
  if (denom <= kTiny) return false;
  const double s = -stiffness * c / denom;
  for (int k = 0; k < 4; ++k) corr[k] = s * w[k] * g[k];
  return true;
}

double stiffness_per_iteration(double stiffness, int iterations) {
  if (iterations <= 1) return stiffness;
  return 1 - std::pow(1 - std::clamp(stiffness, 0.0, 1.0), 1.0 / iterations);
}

}  // namespace tb::pbd
