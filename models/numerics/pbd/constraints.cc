#include "constraints.h"

#include <algorithm>
#include <cmath>

#include "projection_kernels.h"

namespace tb::pbd {
namespace {

using lanes::Triple;

Triple<double> triple(const Vec3& v) { return {v.x(), v.y(), v.z()}; }
Vec3 vec(const Triple<double>& t) { return {t.x, t.y, t.z}; }

/// The signed angle and (if grad) its gradient, zeroed when degenerate.
bool signed_angle(const Vec3& p1, const Vec3& p2, const Vec3& p3, const Vec3& p4, double& theta, Vec3* grad) {
  const Triple<double> p[4] = {triple(p1), triple(p2), triple(p3), triple(p4)};
  Triple<double> g[4];
  const bool ok = kernels::signed_angle(p, theta, grad ? g : nullptr);
  if (grad)
    for (int k = 0; k < 4; ++k) grad[k] = ok ? vec(g[k]) : Vec3::Zero();
  return ok;
}

}  // namespace

double stretch_constraint(const Vec3& p1, const Vec3& p2, double rest_length) { return (p1 - p2).norm() - rest_length; }

void stretch_gradient(const Vec3& p1, const Vec3& p2, Vec3& g1, Vec3& g2) {
  const Vec3 d = p1 - p2;
  const double len = d.norm();
  g1 = len > kTiny ? Vec3(d / len) : Vec3::Zero();
  g2 = -g1;
}

bool project_stretch(const Vec3& p1, double w1, const Vec3& p2, double w2, double rest_length, double stiffness,
                     Vec3& corr1, Vec3& corr2) {
  Triple<double> c1, c2;
  double share1, share2;
  kernels::stretch_shares(w1, w2, share1, share2);
  const bool ok = kernels::project_stretch(triple(p1), share1, triple(p2), share2, rest_length, stiffness, c1, c2);
  corr1 = vec(c1);
  corr2 = vec(c2);
  return ok;
}

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
  const Triple<double> p[4] = {triple(p1), triple(p2), triple(p3), triple(p4)};
  const double w[4] = {w1, w2, w3, w4};
  Triple<double> c[4];
  const bool ok = kernels::project_bending(p, w, rest_angle, stiffness, kind, c);
  for (int k = 0; k < 4; ++k) corr[k] = vec(c[k]);
  return ok;
}

double stiffness_per_iteration(double stiffness, int iterations) {
  if (iterations <= 1) return stiffness;
  return 1 - std::pow(1 - std::clamp(stiffness, 0.0, 1.0), 1.0 / iterations);
}

}  // namespace tb::pbd
