#include "tet_element.h"

#include <Eigen/LU>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace tb {

TetShape tet_shape(const Eigen::Vector3d& X0, const Eigen::Vector3d& X1, const Eigen::Vector3d& X2,
                   const Eigen::Vector3d& X3) {
  Eigen::Matrix3d Dm;  // rest edge matrix [X1 - X0, X2 - X0, X3 - X0]
  Dm << X1 - X0, X2 - X0, X3 - X0;
  const double det = Dm.determinant();
  if (!(std::isfinite(det) && det > 0)) {
    std::ostringstream msg;
    msg << "tet_shape: the tet must be positively oriented, det[X1 - X0, X2 - X0, X3 - X0] > 0, got "
        << std::setprecision(12) << det;
    throw std::invalid_argument(msg.str());
  }
  // N_a for a = 1..3 are the barycentric coordinates Dm^-1 (X - X0), so grad N_a
  // is row a - 1 of Dm^-1, and grad N_0 = -(the sum of the others).
  const Eigen::Matrix3d Dm_inv = Dm.inverse();
  TetShape s;
  s.gradients.rightCols<3>() = Dm_inv.transpose();
  s.gradients.col(0) = -s.gradients.rightCols<3>().rowwise().sum();
  s.volume = det / 6;
  return s;
}

Eigen::Matrix<double, 9, 12> tet_gradient_operator(const TetShape& shape) {
  Eigen::Matrix<double, 9, 12> G = Eigen::Matrix<double, 9, 12>::Zero();
  for (int a = 0; a < 4; ++a)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) G(i + 3 * j, 3 * a + i) = shape.gradients(j, a);
  return G;
}

}  // namespace tb
