#include "stl_writer.h"

#include <Eigen/Geometry>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "atomic_file.h"

namespace tb {

void write_stl(const std::string& path, const SurfaceMesh& m, const std::string& solid_name) {
  const Eigen::Index n = m.V.rows();
  std::ostringstream os;
  os << std::setprecision(17) << "solid " << solid_name << '\n';
  for (Eigen::Index t = 0; t < m.F.rows(); ++t) {
    for (int k = 0; k < 3; ++k)
      if (m.F(t, k) < 0 || m.F(t, k) >= n)
        throw std::runtime_error(path + ": triangle " + std::to_string(t) + " names vertex " +
                                 std::to_string(m.F(t, k)) + " of a surface of " + std::to_string(n) + " vertices");
    const Eigen::Vector3d a = m.V.row(m.F(t, 0)), b = m.V.row(m.F(t, 1)), c = m.V.row(m.F(t, 2));
    Eigen::Vector3d normal = (b - a).cross(c - a);
    const double length = normal.norm();
    normal = length > 0 ? Eigen::Vector3d(normal / length) : Eigen::Vector3d::Zero();
    os << "facet normal " << normal.x() << ' ' << normal.y() << ' ' << normal.z() << "\n outer loop\n";
    for (const Eigen::Vector3d& p : {a, b, c}) os << "  vertex " << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
    os << " endloop\nendfacet\n";
  }
  os << "endsolid " << solid_name << '\n';
  write_file_atomically(path, os.str());
}

}  // namespace tb
