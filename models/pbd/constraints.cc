#include "constraints.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace tb::pbd {
using detail::kTiny;
using detail::signed_angle;

double stretch_constraint(const Vec3& p1, const Vec3& p2, double rest_length) { return (p1 - p2).norm() - rest_length; }

void stretch_gradient(const Vec3& p1, const Vec3& p2, Vec3& g1, Vec3& g2) {
  const Vec3 d = p1 - p2;
  const double len = d.norm();
  g1 = len > kTiny ? Vec3(d / len) : Vec3::Zero();
  g2 = -g1;
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
  if (!signed_angle(p1, p2, p3, p4, theta, g)) {
    for (int k = 0; k < 4; ++k) g[k].setZero();
    return false;
  }
  const double sign = theta < 0 ? -1.0 : 1.0;  // grad |theta| = sign(theta) grad theta
  for (int k = 0; k < 4; ++k) g[k] *= sign;
  return true;
}

bool signed_angle_gradient(const Vec3& p1, const Vec3& p2, const Vec3& p3, const Vec3& p4, Vec3 g[4]) {
  double theta = 0;
  if (signed_angle(p1, p2, p3, p4, theta, g)) return true;
  for (int k = 0; k < 4; ++k) g[k].setZero();
  return false;
}

double stiffness_per_iteration(double stiffness, int iterations) {
  if (iterations <= 1) return stiffness;
  return 1 - std::pow(1 - std::clamp(stiffness, 0.0, 1.0), 1.0 / iterations);
}

}  // namespace tb::pbd
