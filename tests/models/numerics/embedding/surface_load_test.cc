// The disc load's quadrature: mesh-independent points on the surface whose weights
// give the total force and its moment exactly, and its errors.
#include "surface_load.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <limits>

#include "test_support.h"

namespace tb {
namespace {

const HybridMesh& cube() { return testing::scenario_mesh("cube-pull"); }

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "no error";
}

TEST(GaussLegendre, IsExactToDegreeTwoNMinusOne) {
  std::vector<double> s, w;
  for (int n : {1, 3, 8, 32}) {
    gauss_legendre_01(n, s, w);
    for (int k = 0; k <= 2 * n - 1; ++k) {
      double q = 0;
      for (int i = 0; i < n; ++i) q += w[static_cast<size_t>(i)] * std::pow(s[static_cast<size_t>(i)], k);
      EXPECT_NEAR(q, 1.0 / (k + 1), 1e-14) << n << " points, degree " << k;
    }
  }
  EXPECT_THROW(gauss_legendre_01(0, s, w), std::invalid_argument);
}

TEST(DiscLoad, WeightsGiveTheForceAndItsMomentExactlyOnTheSurface) {
  const HybridMesh& h = cube();
  const Eigen::Vector3d centre(0, 0, 0.1);
  const double radius = 0.005;
  const std::vector<LoadPoint> points =
      disc_load_points(h.fine_volume, h.fine_surface, h.fine_surface_to_volume, centre, radius);
  ASSERT_EQ(points.size(), 32u * 128u);
  double total = 0;
  Eigen::Vector3d first_moment = Eigen::Vector3d::Zero();
  double second_moment = 0;
  for (const LoadPoint& p : points) {
    total += p.weight;
    first_moment += p.weight * (p.position - centre);
    second_moment += p.weight * (p.position - centre).squaredNorm();
    EXPECT_EQ(p.position.z(), 0.1) << "on the top face";
    EXPECT_LE((p.position - centre).norm(), radius * (1 + 1e-12));
    // The point lies in its tet (up to round-off).
    ASSERT_GE(p.at.tet, 0);
    double min_coordinate = 1;
    const auto& V = h.fine_volume.V;
    const auto& T = h.fine_volume.T;
    Eigen::Matrix3d M;
    M << V.row(T(p.at.tet, 1)) - V.row(T(p.at.tet, 0)), V.row(T(p.at.tet, 2)) - V.row(T(p.at.tet, 0)),
        V.row(T(p.at.tet, 3)) - V.row(T(p.at.tet, 0));
    const Eigen::Vector3d l = M.transpose().inverse() * (p.position - V.row(T(p.at.tet, 0)).transpose());
    min_coordinate = std::min({1 - l.sum(), l(0), l(1), l(2)});
    EXPECT_GT(min_coordinate, -1e-9);
  }
  EXPECT_NEAR(total, 1, 1e-14);
  EXPECT_LT(first_moment.norm(), 1e-17) << "centred on the load point";
  // A uniform disc: E|x - c|^2 = a^2 / 2.
  EXPECT_NEAR(second_moment, radius * radius / 2, 1e-15);
}

TEST(DiscLoad, BadRadiiAndDiscsOffTheSurfaceAreErrors) {
  const HybridMesh& h = cube();
  auto disc = [&](const Eigen::Vector3d& c, double r) {
    return [&h, c, r] { disc_load_points(h.fine_volume, h.fine_surface, h.fine_surface_to_volume, c, r); };
  };
  for (double r : {-0.001, 0.0, std::nan(""), std::numeric_limits<double>::infinity()}) {
    const std::string e = error_of(disc({0, 0, 0.1}, r));
    EXPECT_NE(e.find("disc radius"), std::string::npos) << r << ": " << e;
    EXPECT_NE(e.find("not a positive length"), std::string::npos) << r << ": " << e;
  }
  // The load point inside the cube, not on its surface.
  std::string e = error_of(disc({0, 0, 0.05}, 0.005));
  EXPECT_NE(e.find("needs its point on the surface"), std::string::npos) << e;
  // A disc wider than the top face: it runs over the cube's edges.
  e = error_of(disc({0, 0, 0.1}, 0.06));
  EXPECT_NE(e.find("leaves the surface"), std::string::npos) << e;
  // Near an edge, a small disc leaves the surface too.
  e = error_of(disc({0.048, 0, 0.1}, 0.005));
  EXPECT_NE(e.find("leaves the surface"), std::string::npos) << e;
}

TEST(PointLoad, OutsideTheVolumeIsAnErrorNamingThePoint) {
  const std::string e = error_of([] { point_load_points(cube().fine_volume, {0, 0, 0.2}); });
  EXPECT_NE(e.find("(0, 0, 0.2) is outside the mesh"), std::string::npos) << e;
  const std::vector<LoadPoint> p = point_load_points(cube().fine_volume, {0, 0, 0.1});
  ASSERT_EQ(p.size(), 1u);
  EXPECT_EQ(p[0].weight, 1.0);
}

}  // namespace
}  // namespace tb
