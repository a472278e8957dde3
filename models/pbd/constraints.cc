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

/// The angle between two vectors, arccos of their normalised dot product computed
/// as atan2(|a x b|, a . b): accurate near 0 and pi, where arccos loses half the
/// digits, and never NaN (the clamp of the arccos argument, done exactly).
double angle_between(const Vec3& a, const Vec3& b) { return std::atan2(a.cross(b).norm(), a.dot(b)); }
}  // namespace

double normal_angle(const Vec3& p1, const Vec3& p2, const Vec3& p3, const Vec3& p4) {
  Vec3 n1, n2;
  wing_normals(p1, p2, p3, p4, n1, n2);
  if (n1.squaredNorm() <= kTiny || n2.squaredNorm() <= kTiny) return 0;
  return angle_between(n1, n2);
}

double bending_constraint(const Vec3& p1, const Vec3& p2, const Vec3& p3, const Vec3& p4, double rest_angle) {
  Vec3 n1, n2;
  wing_normals(p1, p2, p3, p4, n1, n2);
  if (n1.squaredNorm() <= kTiny || n2.squaredNorm() <= kTiny) return 0;
  return angle_between(n1, n2) - rest_angle;
}

namespace {

/// The gradient of C (see bending_gradient) and the angle arccos(n1 . n2), from one
/// set of cross products. Returns false for a degenerate configuration.
bool bending_gradient_and_angle(const Vec3& p1, const Vec3& p2, const Vec3& p3, const Vec3& p4, Vec3 g[4],
                                double& angle) {
  // Bridson, Marino, Fedkiw 2003 (as in Bender's solve_DihedralConstraint): with
  // the shared edge e = p2 - p1 and the wing normals scaled by 1/|n|^2, m3 and m4,
  // the gradient of the signed angle theta between the two normals is (up to one
  // common sign) d theta/d p3 = |e| m3, d theta/d p4 = |e| m4, and for p1, p2 the
  // combinations below from the wings' projections on e: bounded as the
  // triangles become coplanar. arccos(n1 . n2) = |theta|, so
  // grad C = sign(theta) grad theta.
  const Vec3 e = p2 - p1;
  const double elen = e.norm();
  if (elen <= kTiny) return false;
  Vec3 n1, n2;
  wing_normals(p1, p2, p3, p4, n1, n2);
  const double a3 = n1.squaredNorm(), a4 = n2.squaredNorm();
  if (a3 <= kTiny || a4 <= kTiny) return false;
  const Vec3 m3 = n1 / a3, m4 = n2 / a4;
  angle = angle_between(n1, n2);
  // sign(theta): which way n2 is turned from n1 about the edge (checked against
  // finite differences in tests/models/pbd/constraints_test.cc).
  const double sign = n1.cross(n2).dot(e) >= 0 ? -1.0 : 1.0;
  const double inv = 1.0 / elen;
  g[2] = (sign * elen) * m3;
  g[3] = (sign * elen) * m4;
  g[0] = sign * ((p3 - p2).dot(e) * inv * m3 + (p4 - p2).dot(e) * inv * m4);
  g[1] = -sign * ((p3 - p1).dot(e) * inv * m3 + (p4 - p1).dot(e) * inv * m4);
  return true;
}

}  // namespace

bool bending_gradient(const Vec3& p1, const Vec3& p2, const Vec3& p3, const Vec3& p4, Vec3 g[4]) {
  double angle = 0;
  if (bending_gradient_and_angle(p1, p2, p3, p4, g, angle)) return true;
  for (int k = 0; k < 4; ++k) g[k].setZero();
  return false;
}

bool project_bending(const Vec3& p1, double w1, const Vec3& p2, double w2, const Vec3& p3, double w3, const Vec3& p4,
                     double w4, double rest_angle, double stiffness, Vec3 corr[4]) {
  Vec3 g[4];
  double angle = 0;
  if (!bending_gradient_and_angle(p1, p2, p3, p4, g, angle)) {
    for (int k = 0; k < 4; ++k) corr[k].setZero();
    return false;
  }
  const double w[4] = {w1, w2, w3, w4};
  double denom = 0;
  for (int k = 0; k < 4; ++k) denom += w[k] * g[k].squaredNorm();
  if (denom <= kTiny) {
    for (int k = 0; k < 4; ++k) corr[k].setZero();
    return false;
  }
  const double c = angle - rest_angle;
  const double s = -stiffness * c / denom;
  for (int k = 0; k < 4; ++k) corr[k] = s * w[k] * g[k];
  return true;
}

double stiffness_per_iteration(double stiffness, int iterations) {
  if (iterations <= 1) return stiffness;
  return 1 - std::pow(1 - std::clamp(stiffness, 0.0, 1.0), 1.0 / iterations);
}

}  // namespace tb::pbd
