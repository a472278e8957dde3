#include "shapes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <stdexcept>

namespace tb {
namespace {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;

// ---------------------------------------------------------------------------
// Dimensions (m). Every shape is about the cube's size and rests on z = 0.

constexpr double kSphereRadius = 0.05;
const Vec3 kEllipsoidSemiAxes{0.06, 0.04, 0.05};
// Torus standing on its rim (axis along y): tube radius r around a circle of radius R.
constexpr double kTorusMajor = 0.035, kTorusMinor = 0.015;
// Bar along x (length, depth along y, height along z) with a round hole through it along y.
constexpr double kBarLength = 0.12, kBarDepth = 0.05, kBarHeight = 0.06, kBarHoleRadius = 0.015;
// L-block: the L in the x-z plane (a base arm along x, a column up z), extruded along y.
constexpr double kLLength = 0.1, kLBaseHeight = 0.04, kLColumnWidth = 0.04, kLHeight = 0.1, kLDepth = 0.06;
// Dumbbell standing on z: two balls joined by a round neck (creases where they meet).
constexpr double kBallRadius = 0.025, kBallCentreDistance = 0.06, kNeckRadius = 0.011;

constexpr double kReferenceLength = 0.1;  ///< resolution counts segments per this length

/// Segments of a patch edge of `length` for target edge length h: at least `min`.
int segments(double length, double h, int min = 1) { return std::max(min, static_cast<int>(std::lround(length / h))); }
/// An even segment count (the midpoint is then a vertex).
int even_segments(double length, double h) { return 2 * segments(length / 2, h); }

/// Samples of [a, b] at n + 1 equally spaced points.
std::vector<double> samples(double a, double b, int n) {
  std::vector<double> s(static_cast<size_t>(n) + 1);
  for (int i = 0; i <= n; ++i) s[static_cast<size_t>(i)] = i == n ? b : a + (b - a) * i / n;
  return s;
}

// ---------------------------------------------------------------------------
// Structured patches welded into one surface.

/// Triangles from structured quad patches; points of different patches closer
/// than the weld tolerance become one vertex (shared patch edges are computed by
/// different formulas, so they agree to round-off only). Vertices are numbered in
/// order of first appearance, so the result is deterministic.
class PatchSurface {
 public:
  explicit PatchSurface(double weld_tolerance) : tol_(weld_tolerance), cell_(4 * weld_tolerance) {}

  /// A grid patch of ns x nt quads: P has (ns + 1) * (nt + 1) points, P[i * (nt + 1) + j]
  /// at parameter (i, j). Each quad is split along its shorter diagonal (alternating by
  /// i + j when both are as long). Triangles face along dP/di x dP/dj, or the opposite if `flip`.
  void add_grid(const std::vector<Vec3>& P, int ns, int nt, bool flip) {
    std::vector<int> id(P.size());
    for (size_t k = 0; k < P.size(); ++k) id[k] = vertex(P[k]);
    auto at = [&](int i, int j) { return static_cast<size_t>(i * (nt + 1) + j); };
    for (int i = 0; i < ns; ++i)
      for (int j = 0; j < nt; ++j) {
        const size_t a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
        const double ac = (P[a] - P[c]).norm(), bd = (P[b] - P[d]).norm();
        const bool split_ac = std::abs(ac - bd) <= 1e-9 * (ac + bd) ? (i + j) % 2 == 0 : ac < bd;
        if (split_ac) {
          triangle(id[a], id[b], id[c], flip);
          triangle(id[a], id[c], id[d], flip);
        } else {
          triangle(id[a], id[b], id[d], flip);
          triangle(id[b], id[c], id[d], flip);
        }
      }
  }

  /// One triangle a, b, c (counter-clockwise seen from outside).
  void add_triangle(const Vec3& a, const Vec3& b, const Vec3& c) { triangle(vertex(a), vertex(b), vertex(c), false); }

  SurfaceMesh mesh() const {
    SurfaceMesh m;
    m.V.resize(static_cast<Eigen::Index>(points_.size()), 3);
    for (size_t v = 0; v < points_.size(); ++v) m.V.row(static_cast<Eigen::Index>(v)) = points_[v].transpose();
    m.F.resize(static_cast<Eigen::Index>(triangles_.size()), 3);
    for (size_t t = 0; t < triangles_.size(); ++t)
      for (int k = 0; k < 3; ++k) m.F(static_cast<Eigen::Index>(t), k) = triangles_[t][static_cast<size_t>(k)];
    return m;
  }

 private:
  using Cell = std::array<long long, 3>;
  Cell cell_of(const Vec3& p) const {
    return {std::llround(std::floor(p.x() / cell_)), std::llround(std::floor(p.y() / cell_)),
            std::llround(std::floor(p.z() / cell_))};
  }
  /// The index of p: an earlier point within the tolerance, else a new vertex.
  int vertex(const Vec3& p) {
    const Cell c = cell_of(p);
    for (long long dx = -1; dx <= 1; ++dx)
      for (long long dy = -1; dy <= 1; ++dy)
        for (long long dz = -1; dz <= 1; ++dz) {
          const auto it = cells_.find({c[0] + dx, c[1] + dy, c[2] + dz});
          if (it == cells_.end()) continue;
          for (int v : it->second)
            if ((points_[static_cast<size_t>(v)] - p).norm() <= tol_) return v;
        }
    points_.push_back(p);
    const int v = static_cast<int>(points_.size()) - 1;
    cells_[c].push_back(v);
    return v;
  }
  void triangle(int a, int b, int c, bool flip) {
    if (a == b || b == c || a == c) throw std::logic_error("shape generator: a patch quad collapsed to a triangle");
    triangles_.push_back(flip ? std::array<int, 3>{a, c, b} : std::array<int, 3>{a, b, c});
  }

  double tol_, cell_;
  std::vector<Vec3> points_;
  std::vector<std::array<int, 3>> triangles_;
  std::map<Cell, std::vector<int>> cells_;
};

/// Points of a grid patch from its parametrisation: P[i * (nt + 1) + j] = f(i, j).
std::vector<Vec3> grid_points(int ns, int nt, const std::function<Vec3(int, int)>& f) {
  std::vector<Vec3> P;
  P.reserve(static_cast<size_t>((ns + 1) * (nt + 1)));
  for (int i = 0; i <= ns; ++i)
    for (int j = 0; j <= nt; ++j) P.push_back(f(i, j));
  return P;
}

constexpr double kWeldTolerance = 1e-10;  ///< m: far below any edge, far above round-off

// ---------------------------------------------------------------------------
// Cube sphere: the six faces of a cube, equiangularly mapped onto a unit sphere.

/// Unit-sphere cube sphere with n x n quads per face, each face's normal outward.
/// `map` takes a unit-sphere point to the shape (an orientation-preserving map).
SurfaceMesh cube_sphere(int n, const std::function<Vec3(const Vec3&)>& map) {
  // (normal, u, v) with u x v = normal, so the (i, j) grid faces outward.
  const std::array<std::array<Vec3, 3>, 6> faces{{{Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ()},
                                                  {-Vec3::UnitX(), Vec3::UnitZ(), Vec3::UnitY()},
                                                  {Vec3::UnitY(), Vec3::UnitZ(), Vec3::UnitX()},
                                                  {-Vec3::UnitY(), Vec3::UnitX(), Vec3::UnitZ()},
                                                  {Vec3::UnitZ(), Vec3::UnitX(), Vec3::UnitY()},
                                                  {-Vec3::UnitZ(), Vec3::UnitY(), Vec3::UnitX()}}};
  PatchSurface s(kWeldTolerance);
  for (const auto& face : faces) {
    // References, not structured bindings: a C++17 lambda cannot capture those.
    const Vec3 &normal = face[0], &u = face[1], &v = face[2];
    auto tangent = [n](int i) { return std::tan(M_PI / 4 * (2.0 * i / n - 1)); };  // equiangular
    s.add_grid(
        grid_points(n, n, [&](int i, int j) { return map((normal + tangent(i) * u + tangent(j) * v).normalized()); }),
        n, n, false);
  }
  return s.mesh();
}

SurfaceMesh sphere(double h) {
  const int n = even_segments(M_PI / 2 * kSphereRadius, h);  // a face spans a quarter circle
  return cube_sphere(n, [](const Vec3& p) { return Vec3(kSphereRadius * p + Vec3(0, 0, kSphereRadius)); });
}

SurfaceMesh ellipsoid(double h) {
  const int n = even_segments(M_PI / 2 * kEllipsoidSemiAxes.mean(), h);  // cells from 0.8 h to 1.2 h
  return cube_sphere(
      n, [](const Vec3& p) { return Vec3(kEllipsoidSemiAxes.cwiseProduct(p) + Vec3(0, 0, kEllipsoidSemiAxes.z())); });
}

// ---------------------------------------------------------------------------
// Torus: a periodic (u, v) grid, standing on its rim in the x-z plane.

SurfaceMesh torus(double h) {
  const int nu = 4 * segments(2 * M_PI * kTorusMajor / 4, h);  // multiple of 4: top and bottom are vertices
  const int nv = even_segments(2 * M_PI * kTorusMinor, h);
  const Vec3 centre(0, 0, kTorusMajor + kTorusMinor);
  PatchSurface s(kWeldTolerance);
  s.add_grid(grid_points(nu, nv,
                         [&](int i, int j) {
                           const double u = 2 * M_PI * i / nu, v = 2 * M_PI * j / nv;
                           const Vec3 radial(std::cos(u), 0, std::sin(u));  // in the x-z plane
                           return Vec3(centre + (kTorusMajor + kTorusMinor * std::cos(v)) * radial +
                                       kTorusMinor * std::sin(v) * Vec3::UnitY());
                         }),
             nu, nv, true);  // d/du x d/dv points into the tube
  return s.mesh();
}

// ---------------------------------------------------------------------------
// Extrusions: a 2D grid in the (a, b) plane, extruded along c.

/// The closed surface of a 2D region extruded over c in `c_samples` (ascending):
/// the two caps and, along every boundary edge, a strip of quads. `region` holds
/// points (a, b, 0) and triangles counter-clockwise in (a, b), as PatchSurface
/// builds them from (a, b) grids. `place` maps (a, b, c) to the shape's frame
/// (a rotation and a shift, so orientation is kept).
SurfaceMesh extrude(const SurfaceMesh& region, const std::vector<double>& c_samples,
                    const std::function<Vec3(const Vec3&)>& place) {
  const int nc = static_cast<int>(c_samples.size()) - 1;
  PatchSurface s(kWeldTolerance);
  auto at = [&](int v, double c) { return place(Vec3(region.V(v, 0), region.V(v, 1), c)); };
  // Caps: a counter-clockwise (a, b) triangle faces +c, outward at the top cap.
  for (Eigen::Index t = 0; t < region.F.rows(); ++t) {
    const int a = region.F(t, 0), b = region.F(t, 1), c = region.F(t, 2);
    s.add_triangle(at(a, c_samples.back()), at(b, c_samples.back()), at(c, c_samples.back()));
    s.add_triangle(at(a, c_samples.front()), at(c, c_samples.front()), at(b, c_samples.front()));
  }
  // Walls: boundary edges are in one triangle only, directed as in it (region on
  // their left); (q - p) x c is then the outward normal.
  std::map<std::pair<int, int>, int> directed;
  for (Eigen::Index t = 0; t < region.F.rows(); ++t)
    for (int k = 0; k < 3; ++k) directed[{region.F(t, k), region.F(t, (k + 1) % 3)}] = 1;
  for (const auto& edge : directed) {
    const int p = edge.first.first, q = edge.first.second;
    if (directed.count({q, p})) continue;  // interior edge
    s.add_grid(grid_points(1, nc, [&](int i, int j) { return at(i == 0 ? p : q, c_samples[static_cast<size_t>(j)]); }),
               1, nc, false);
  }
  return s.mesh();
}

/// A 2D (a, b) grid patch as points (a, b, 0), for extrude.
std::vector<Vec3> plane_grid(int ns, int nt, const std::function<Vec2(int, int)>& f) {
  return grid_points(ns, nt, [&](int i, int j) {
    const Vec2 p = f(i, j);
    return Vec3(p.x(), p.y(), 0);
  });
}

/// (a, b, c) -> (x, y, z) = (a, -c, b + shift_z): the (a, b) plane becomes x-z, c runs along -y.
std::function<Vec3(const Vec3&)> stand_up(double shift_z) {
  return [shift_z](const Vec3& p) { return Vec3(p.x(), -p.z(), p.y() + shift_z); };
}

/// Point j of n on the boundary of the square [-s, s]^2, counter-clockwise from
/// the corner (s, -s), equally spaced along each side (n a multiple of 4).
Vec2 square_perimeter(double s, int n, int j) {
  const std::array<Vec2, 5> corners{Vec2(s, -s), Vec2(s, s), Vec2(-s, s), Vec2(-s, -s), Vec2(s, -s)};
  const int per_side = n / 4, side = (j / per_side) % 4;
  const double f = static_cast<double>(j % per_side) / per_side;
  return corners[static_cast<size_t>(side)] +
         f * (corners[static_cast<size_t>(side) + 1] - corners[static_cast<size_t>(side)]);
}
/// Point j of n on the circle of radius r, starting at -45 degrees (with square_perimeter's corner).
Vec2 circle_point(double r, int n, int j) {
  const double angle = -M_PI / 4 + 2 * M_PI * j / n;
  return r * Vec2(std::cos(angle), std::sin(angle));
}

/// Bar along x with a round hole along y, as the extrusion of a rectangle with a
/// hole: a square O-grid around the hole (rings from the circle to the square)
/// between two rectangular end blocks.
SurfaceMesh bar_with_hole(double h) {
  const double half_square = kBarHeight / 2, end_length = (kBarLength - kBarHeight) / 2;
  const int n_side = even_segments(kBarHeight, h), n_around = 4 * n_side;
  const int n_end = segments(end_length, h);
  // Rings: the mean distance from the circle to the square's sides and corners.
  const int n_rings = segments(half_square * (1 + std::sqrt(2.0)) / 2 - kBarHoleRadius, h);
  PatchSurface region(kWeldTolerance);
  region.add_grid(plane_grid(n_rings, n_around,
                             [&](int k, int j) {
                               const double f = static_cast<double>(k) / n_rings;
                               return Vec2((1 - f) * circle_point(kBarHoleRadius, n_around, j) +
                                           f * square_perimeter(half_square, n_around, j));
                             }),
                  n_rings, n_around, false);
  for (int side : {-1, 1}) {
    const std::vector<double> a = samples(side * half_square, side * (half_square + end_length), n_end);
    const std::vector<double> b = samples(-half_square, half_square, n_side);
    region.add_grid(
        plane_grid(n_end, n_side,
                   [&](int i, int j) { return Vec2(a[static_cast<size_t>(i)], b[static_cast<size_t>(j)]); }),
        n_end, n_side, side < 0);  // a decreasing on the left: flip back to counter-clockwise
  }
  return extrude(region.mesh(), samples(-kBarDepth / 2, kBarDepth / 2, even_segments(kBarDepth, h)),
                 stand_up(kBarHeight / 2));
}

/// L-block: the L (a base arm along x, a column up z at the -x end) extruded along
/// y, as three rectangles (the corner, the arm, the column) with matching edges.
SurfaceMesh l_block(double h) {
  const double x0 = -kLLength / 2, x1 = x0 + kLColumnWidth, x2 = x0 + kLLength;
  const int n_column = even_segments(kLColumnWidth, h), n_arm = segments(kLLength - kLColumnWidth, h);
  const int n_base = segments(kLBaseHeight, h), n_up = segments(kLHeight - kLBaseHeight, h);
  PatchSurface region(kWeldTolerance);
  auto rectangle = [&](double a0, double a1, int na, double b0, double b1, int nb) {
    const std::vector<double> a = samples(a0, a1, na), b = samples(b0, b1, nb);
    region.add_grid(
        plane_grid(na, nb, [&](int i, int j) { return Vec2(a[static_cast<size_t>(i)], b[static_cast<size_t>(j)]); }),
        na, nb, false);
  };
  rectangle(x0, x1, n_column, 0, kLBaseHeight, n_base);
  rectangle(x1, x2, n_arm, 0, kLBaseHeight, n_base);
  rectangle(x0, x1, n_column, kLBaseHeight, kLHeight, n_up);
  return extrude(region.mesh(), samples(-kLDepth / 2, kLDepth / 2, even_segments(kLDepth, h)), stand_up(0));
}

// ---------------------------------------------------------------------------
// Dumbbell: a surface of revolution about z. Its two poles are covered by disk
// caps (a square grid and rings out to the circle, mapped onto the ball's outer
// hemisphere) so no triangle fans into a pole; the band between the caps is a
// periodic grid over the profile (ball, neck, ball) and the angle.

SurfaceMesh dumbbell(double h) {
  const int n_around = 8 * segments(2 * M_PI * kBallRadius / 8, h);  // caps' squares have an even side
  const int n_square = n_around / 4;
  const double half_square = 0.5;  // of the unit disk: square cells about as long as the rim's
  const int n_rings = segments((1 - half_square) * M_PI / 2 * kBallRadius, h);
  const double z_low = kBallRadius, z_high = kBallRadius + kBallCentreDistance;

  PatchSurface s(kWeldTolerance);
  // Caps: unit disk point w -> polar angle (pi / 2) |w| from the pole (azimuthal equidistant).
  for (int side : {-1, 1}) {
    const double z_centre = side < 0 ? z_low : z_high;
    auto on_ball = [&](const Vec2& w) {
      const double phi = M_PI / 2 * w.norm(), psi = std::atan2(w.y(), w.x());
      return Vec3(kBallRadius * std::sin(phi) * std::cos(psi), kBallRadius * std::sin(phi) * std::sin(psi),
                  z_centre + side * kBallRadius * std::cos(phi));
    };
    const std::vector<double> q = samples(-half_square, half_square, n_square);
    s.add_grid(
        grid_points(n_square, n_square,
                    [&](int i, int j) { return on_ball(Vec2(q[static_cast<size_t>(i)], q[static_cast<size_t>(j)])); }),
        n_square, n_square, side < 0);  // counter-clockwise from above faces up: flip at the bottom
    s.add_grid(grid_points(n_rings, n_around,
                           [&](int k, int j) {
                             const double f = static_cast<double>(k) / n_rings;
                             return on_ball((1 - f) * square_perimeter(half_square, n_around, j) +
                                            f * circle_point(1.0, n_around, j));
                           }),
               n_rings, n_around, side < 0);
  }
  // Profile from the lower ball's equator up to the upper ball's equator: (radius, z).
  const double neck_angle = std::acos(kNeckRadius / kBallRadius);  // elevation where the ball meets the neck
  const double neck_low = z_low + kBallRadius * std::sin(neck_angle),
               neck_high = z_high - kBallRadius * std::sin(neck_angle);
  std::vector<Vec2> profile;
  const int n_ball = segments(kBallRadius * neck_angle, h), n_neck = segments(neck_high - neck_low, h);
  for (int k = 0; k < n_ball; ++k) {
    const double e = neck_angle * k / n_ball;
    profile.emplace_back(kBallRadius * std::cos(e), z_low + kBallRadius * std::sin(e));
  }
  for (int k = 0; k < n_neck; ++k) profile.emplace_back(kNeckRadius, neck_low + (neck_high - neck_low) * k / n_neck);
  for (int k = 0; k <= n_ball; ++k) {
    const double e = neck_angle * (1 - static_cast<double>(k) / n_ball);
    profile.emplace_back(kBallRadius * std::cos(e), z_high - kBallRadius * std::sin(e));
  }
  const int n_profile = static_cast<int>(profile.size()) - 1;
  s.add_grid(grid_points(n_profile, n_around,
                         [&](int k, int j) {
                           const Vec2 rim = circle_point(1.0, n_around, j);
                           const Vec2 rz = profile[static_cast<size_t>(k)];
                           return Vec3(rz.x() * rim.x(), rz.x() * rim.y(), rz.y());
                         }),
             n_profile, n_around, true);  // up x around points into the axis
  return s.mesh();
}

}  // namespace

const std::vector<std::string>& shape_names() {
  static const std::vector<std::string> names{"sphere", "ellipsoid", "torus", "bar_with_hole", "l_block", "dumbbell"};
  return names;
}

std::string shape_description(const std::string& name) {
  if (name == "sphere") return "sphere, radius 0.05 m (cube sphere: six equiangular grids)";
  if (name == "ellipsoid") return "ellipsoid, semi-axes 0.06 x 0.04 x 0.05 m (cube sphere, scaled)";
  if (name == "torus")
    return "torus standing on its rim in the x-z plane, radii 0.035 m and 0.015 m (tube), 0.1 m high";
  if (name == "bar_with_hole")
    return "bar 0.12 x 0.05 x 0.06 m (x, y, z) with a round hole of radius 0.015 m through it along y";
  if (name == "l_block")
    return "L-block: a 0.1 x 0.04 m base arm and a 0.04 m wide column 0.1 m high in x-z, 0.06 m deep in y";
  if (name == "dumbbell")
    return "dumbbell standing on z: balls of radius 0.025 m, centres 0.06 m apart, neck radius 0.011 m";
  throw std::invalid_argument("unknown shape '" + name + "'");
}

SurfaceMesh make_shape_surface(const ShapeSpec& spec) {
  std::string known;
  for (const auto& n : shape_names()) known += (known.empty() ? "" : ", ") + n;
  if (std::find(shape_names().begin(), shape_names().end(), spec.name) == shape_names().end())
    throw std::invalid_argument("unknown shape '" + spec.name + "' (one of " + known + ")");
  if (spec.resolution < kMinShapeResolution || spec.resolution > kMaxShapeResolution)
    throw std::invalid_argument("shape resolution " + std::to_string(spec.resolution) + " outside [" +
                                std::to_string(kMinShapeResolution) + ", " + std::to_string(kMaxShapeResolution) + "]");
  const double h = kReferenceLength / spec.resolution;
  if (spec.name == "sphere") return sphere(h);
  if (spec.name == "ellipsoid") return ellipsoid(h);
  if (spec.name == "torus") return torus(h);
  if (spec.name == "bar_with_hole") return bar_with_hole(h);
  if (spec.name == "l_block") return l_block(h);
  return dumbbell(h);
}

double shape_exact_volume(const std::string& name) {
  if (name == "sphere") return 4.0 / 3 * M_PI * std::pow(kSphereRadius, 3);
  if (name == "ellipsoid") return 4.0 / 3 * M_PI * kEllipsoidSemiAxes.prod();
  if (name == "torus") return 2 * M_PI * M_PI * kTorusMajor * kTorusMinor * kTorusMinor;
  if (name == "bar_with_hole") return (kBarLength * kBarHeight - M_PI * kBarHoleRadius * kBarHoleRadius) * kBarDepth;
  if (name == "l_block") return (kLLength * kLBaseHeight + kLColumnWidth * (kLHeight - kLBaseHeight)) * kLDepth;
  if (name == "dumbbell") {
    // Two balls less the caps cut off by the neck, plus the neck between the cuts.
    const double cut = std::sqrt(kBallRadius * kBallRadius - kNeckRadius * kNeckRadius);
    const double cap_height = kBallRadius - cut;
    const double cap = M_PI * cap_height * cap_height * (3 * kBallRadius - cap_height) / 3;
    return 2 * (4.0 / 3 * M_PI * std::pow(kBallRadius, 3) - cap) +
           M_PI * kNeckRadius * kNeckRadius * (kBallCentreDistance - 2 * cut);
  }
  throw std::invalid_argument("unknown shape '" + name + "'");
}

}  // namespace tb
