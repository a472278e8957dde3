// The support box (load_case.h): which nodes it clamps, and whether that holds a body.
#include <Eigen/Geometry>
#include <sstream>
#include <stdexcept>

#include "load_case.h"

namespace tb {

std::vector<char> SupportBox::select(const Points& V) const {
  std::vector<char> out(static_cast<size_t>(V.rows()));
  for (Eigen::Index i = 0; i < V.rows(); ++i) out[static_cast<size_t>(i)] = contains(V.row(i).transpose());
  return out;
}

namespace {

/// Whether the clamped points span at least a plane's worth of directions: two
/// distinct points and a third off their line (relative to the mesh size).
bool has_three_non_collinear(const Points& V, const std::vector<char>& clamped) {
  const double size = V.rows() ? (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm() : 0;
  const double eps = 1e-9 * size;
  int a = -1, b = -1;
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    if (!clamped[static_cast<size_t>(i)]) continue;
    if (a < 0) {
      a = static_cast<int>(i);
    } else if (b < 0) {
      if ((V.row(i) - V.row(a)).norm() > eps) b = static_cast<int>(i);
    } else {
      const Eigen::Vector3d ab = (V.row(b) - V.row(a)).transpose(), ac = (V.row(i) - V.row(a)).transpose();
      if (ab.cross(ac).norm() > eps * ab.norm()) return true;
    }
  }
  return false;
}

}  // namespace

std::vector<char> SupportBox::clamp(const Points& V, const std::string& mesh_name) const {
  std::vector<char> c = select(V);
  if (has_three_non_collinear(V, c)) return c;
  int count = 0;
  for (char x : c) count += x;
  auto point = [](const Eigen::Vector3d& p) {
    std::ostringstream os;
    os << "(" << p.x() << ", " << p.y() << ", " << p.z() << ")";
    return os.str();
  };
  std::ostringstream msg;
  msg << "support box " << point(min) << " to " << point(max) << " clamps " << count << " of the " << V.rows()
      << " nodes of the " << mesh_name << (count >= 3 ? ", all on one line" : "")
      << ": at least three nodes not on one line must be clamped to hold the body (rigid motions are left free)";
  throw std::invalid_argument(msg.str());
}

}  // namespace tb
