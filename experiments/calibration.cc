#include "calibration.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <stdexcept>

#include "build_info.h"
#include "lame_parameters.h"
#include "neo_hookean.h"
#include "strict_json.h"
#include "tet_element.h"

namespace tb {
namespace {

constexpr int kCells = 16;   ///< cells along each side of the unit cube: 24 576 tets, 4 913 nodes
constexpr int kSweeps = 96;  ///< over every tet, in one repeat: about 0.1 s on the 2-core CI machine

/// A structured mesh of the unit cube: each cell split into the six tets around its
/// main diagonal (Kuhn's split), every tet positively oriented.
struct CalibrationMesh {
  std::vector<Eigen::Vector3d> rest;
  std::vector<std::array<int, 4>> tets;
  std::vector<TetShape> shapes;
};

CalibrationMesh make_mesh() {
  CalibrationMesh m;
  const int n = kCells + 1;
  auto node = [n](int i, int j, int k) { return i + n * (j + n * k); };
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) m.rest.push_back(Eigen::Vector3d(double(i), double(j), double(k)) / double(kCells));
  const std::array<std::array<int, 3>, 6> orders{{{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}}};
  for (int k = 0; k < kCells; ++k)
    for (int j = 0; j < kCells; ++j)
      for (int i = 0; i < kCells; ++i)
        for (const auto& order : orders) {
          std::array<int, 3> at{i, j, k};
          std::array<int, 4> tet{};
          tet[0] = node(at[0], at[1], at[2]);
          for (size_t s = 0; s < 3; ++s) {
            ++at[static_cast<size_t>(order[s])];  // one step along each axis, in this tet's order
            tet[s + 1] = node(at[0], at[1], at[2]);
          }
          Eigen::Matrix3d edges;
          edges << m.rest[tet[1]] - m.rest[tet[0]], m.rest[tet[2]] - m.rest[tet[0]], m.rest[tet[3]] - m.rest[tet[0]];
          if (edges.determinant() < 0) std::swap(tet[2], tet[3]);
          m.tets.push_back(tet);
          m.shapes.push_back(tet_shape(m.rest[tet[0]], m.rest[tet[1]], m.rest[tet[2]], m.rest[tet[3]]));
        }
  return m;
}

/// One repeat: kSweeps sweeps of forces f_a = -V P(F) g_a over every tet, at a fixed
/// smooth deformation (a twist and a stretch, no tet inverted). Returns a checksum.
double sweep(const CalibrationMesh& m, const std::vector<Eigen::Vector3d>& x, std::vector<Eigen::Vector3d>& f,
             const NeoHookean& law) {
  double checksum = 0;
  for (int s = 0; s < kSweeps; ++s) {
    std::fill(f.begin(), f.end(), Eigen::Vector3d::Zero());
    for (size_t t = 0; t < m.tets.size(); ++t) {
      const std::array<int, 4>& tet = m.tets[t];
      Eigen::Matrix<double, 3, 4> xt;
      for (int a = 0; a < 4; ++a) xt.col(a) = x[static_cast<size_t>(tet[static_cast<size_t>(a)])];
      const TetShape& shape = m.shapes[t];
      const Eigen::Matrix<double, 3, 4> forces =
          -shape.volume * law.first_piola(tet_deformation_gradient(shape, xt)) * shape.gradients;
      for (int a = 0; a < 4; ++a) f[static_cast<size_t>(tet[static_cast<size_t>(a)])] += forces.col(a);
    }
    checksum += f[f.size() / 3].norm();
  }
  return checksum;
}

}  // namespace

std::string calibration_workload() {
  return "P1 tet loop: " + std::to_string(kSweeps) + " sweeps of the neo-Hookean nodal forces over the " +
         std::to_string(6 * kCells * kCells * kCells) + " tets of a " + std::to_string(kCells) + "^3-cell cube " +
         "(experiments/calibration.cc), one thread";
}

Calibration run_calibration(int repeats) {
  if (repeats < 1) throw std::invalid_argument("calibrate: --repeats must be at least 1");
  const CalibrationMesh mesh = make_mesh();
  std::vector<Eigen::Vector3d> x = mesh.rest;
  for (Eigen::Vector3d& p : x) {
    const double angle = 0.2 * p.z();
    p = Eigen::Vector3d(std::cos(angle) * p.x() - std::sin(angle) * p.y(),
                        std::sin(angle) * p.x() + std::cos(angle) * p.y(), 1.1 * p.z());
  }
  std::vector<Eigen::Vector3d> f(x.size());
  const NeoHookean law(lame_parameters(3000.0, 0.45));
  Calibration c;
  c.checksum = sweep(mesh, x, f, law);  // warm-up: caches, frequency
  for (int r = 0; r < repeats; ++r) {
    const auto start = std::chrono::steady_clock::now();
    const double sum = sweep(mesh, x, f, law);
    c.times_ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    if (sum != c.checksum) throw std::logic_error("calibrate: the workload gave two answers");
  }
  // The fastest repeat: other work on the machine only ever adds time, so the minimum
  // is the steadiest figure of the machine's own speed (at a load average of 7 on a
  // 2-core machine the repeats spread from 98 to 215 ms and the median nearly doubled,
  // the minimum stayed within a few per cent of the quiet machine's).
  c.figure_ms = *std::min_element(c.times_ms.begin(), c.times_ms.end());
  const nlohmann::json info = build_and_machine_info();
  c.machine = {{"cpu", info.value("cpu_model", "unknown")},
               {"cores", info["hardware_threads"]},
               {"hostname", info["hostname"]},
               {"build_type", info["build_type"]},
               {"compiler", info["compiler"]},
               {"git_commit", info["git_commit"]},
               {"load_average_1min", load_average_1min()}};  // a loaded machine's figure is slower
  return c;
}

nlohmann::json Calibration::to_json() const {
  return {{"figure_ms", figure_ms}, {"repeats", times_ms.size()},
          {"times_ms", times_ms},   {"workload", calibration_workload()},
          {"checksum", checksum},   {"machine", machine}};
}

double calibration_figure(const std::string& value) {
  char* end = nullptr;
  const double number = std::strtod(value.c_str(), &end);
  if (!value.empty() && end == value.c_str() + value.size()) {
    if (!(std::isfinite(number) && number > 0))
      throw std::invalid_argument("--calibration " + value + ": a figure must be a positive number of ms");
    return number;
  }
  StrictObject o(read_json_file(value), value);
  return o.number("figure_ms", std::nullopt, 1e-6, 1e12);
}

}  // namespace tb
