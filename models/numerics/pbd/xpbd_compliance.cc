#include "xpbd_compliance.h"

#include <Eigen/Geometry>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>

#include "mesh_checks.h"

namespace tb::pbd {
namespace {

double triangle_area(const Points& V, int a, int b, int c) {
  return 0.5 * (V.row(b) - V.row(a)).cross(V.row(c) - V.row(a)).norm();
}

void check_material(double youngs_modulus, double thickness) {
  if (!(youngs_modulus > 0))
    throw std::invalid_argument("XPBD compliance: Young's modulus must be > 0 (" + std::to_string(youngs_modulus) +
                                " given)");
  if (!(thickness > 0))
    throw std::invalid_argument("XPBD compliance: shell thickness must be > 0 (" + std::to_string(thickness) +
                                " m given)");
}

[[noreturn]] void degenerate(const char* kind, Eigen::Index row) {
  throw std::invalid_argument(std::string("XPBD compliance: ") + kind + " constraint " + std::to_string(row) +
                              " has zero rest length or zero area: no stiffness can be derived for it");
}

}  // namespace

double volume_preserving_thickness(const SurfaceMesh& s) {
  double area = 0;
  for (Eigen::Index t = 0; t < s.F.rows(); ++t) area += triangle_area(s.V, s.F(t, 0), s.F(t, 1), s.F(t, 2));
  const double volume = enclosed_volume(s);
  if (!(area > 0) || !(volume > 0))
    throw std::invalid_argument("XPBD: the surface encloses no volume; give shell_thickness explicitly");
  return volume / area;
}

Eigen::VectorXd stretch_compliances(const SurfaceMesh& s, const KindConstraints& c, double E, double h) {
  check_material(E, h);
  std::map<std::pair<int, int>, double> edge_area;  // A_e: the areas of the triangles sharing each edge
  for (Eigen::Index t = 0; t < s.F.rows(); ++t) {
    const double A = triangle_area(s.V, s.F(t, 0), s.F(t, 1), s.F(t, 2));
    for (int k = 0; k < 3; ++k) {
      const int a = s.F(t, k), b = s.F(t, (k + 1) % 3);
      edge_area[{std::min(a, b), std::max(a, b)}] += A;
    }
  }
  Eigen::VectorXd alpha(c.size());
  for (Eigen::Index i = 0; i < c.size(); ++i) {
    const int a = c.vertices(i, 0), b = c.vertices(i, 1);
    const auto found = edge_area.find({std::min(a, b), std::max(a, b)});
    const double L = c.rest(i, 0), A = found == edge_area.end() ? 0.0 : found->second;
    if (!(L > 0) || !(A > 0)) degenerate("stretch", i);
    alpha(i) = L * L / (E * h * A);  // 1 / k_e, k_e = E h A_e / L_e^2
  }
  return alpha;
}

Eigen::VectorXd bending_compliances(const SurfaceMesh& s, const KindConstraints& c, double E, double nu, double h) {
  check_material(E, h);
  if (!(nu > -1 && nu <= 0.5))
    throw std::invalid_argument("XPBD compliance: Poisson's ratio must lie in (-1, 0.5] (" + std::to_string(nu) +
                                " given)");
  const double D = E * h * h * h / (12 * (1 - nu * nu));  // flexural rigidity, N m
  Eigen::VectorXd alpha(c.size());
  for (Eigen::Index i = 0; i < c.size(); ++i) {
    const int p1 = c.vertices(i, 0), p2 = c.vertices(i, 1), p3 = c.vertices(i, 2), p4 = c.vertices(i, 3);
    const double L = (s.V.row(p2) - s.V.row(p1)).norm();
    const double A = triangle_area(s.V, p1, p2, p3) + triangle_area(s.V, p2, p1, p4);
    if (!(L > 0) || !(A > 0)) degenerate("bending", i);
    alpha(i) = A / (3 * D * L * L);  // 1 / k_e, k_e = 3 D L_e^2 / A_e
  }
  return alpha;
}

}  // namespace tb::pbd
