#include "point_grid.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace tb {

PointGrid::PointGrid(const Points& points, double cell) : cell_(cell), count_(static_cast<int>(points.rows())) {
  if (!(std::isfinite(cell) && cell > 0)) throw std::invalid_argument("PointGrid: the cell size must be positive");
  if (points.rows() == 0) {
    origin_.setZero();
    dims_.setOnes();
    start_.assign(2, 0);
    return;
  }
  origin_ = points.colwise().minCoeff().transpose();
  const Eigen::Vector3d extent = points.colwise().maxCoeff().transpose() - origin_;
  // Cells beyond 2^20 per axis or 2^24 in all would only cost memory: widen the cell.
  for (;;) {
    for (int k = 0; k < 3; ++k) dims_(k) = static_cast<int>(std::floor(extent(k) / cell_)) + 1;
    if (dims_.cast<double>().prod() <= std::max(1 << 24, 8 * count_)) break;
    cell_ *= 2;
  }
  const auto cell_of = [&](Eigen::Index p) {
    Eigen::Array3i c;
    for (int k = 0; k < 3; ++k)
      c(k) = std::clamp(static_cast<int>(std::floor((points(p, k) - origin_(k)) / cell_)), 0, dims_(k) - 1);
    return (c(2) * dims_(1) + c(1)) * dims_(0) + c(0);
  };
  const int cells = dims_.prod();
  start_.assign(static_cast<size_t>(cells) + 1, 0);
  for (Eigen::Index p = 0; p < points.rows(); ++p) ++start_[static_cast<size_t>(cell_of(p)) + 1];
  for (int c = 0; c < cells; ++c) start_[static_cast<size_t>(c) + 1] += start_[static_cast<size_t>(c)];
  points_.resize(static_cast<size_t>(count_));
  std::vector<int> fill(start_.begin(), start_.end() - 1);
  for (Eigen::Index p = 0; p < points.rows(); ++p)
    points_[static_cast<size_t>(fill[static_cast<size_t>(cell_of(p))]++)] = static_cast<int>(p);
}

void PointGrid::query(const Eigen::Vector3d& centre, double radius, std::vector<int>& out) const {
  out.clear();
  Eigen::Array3i lo, hi;
  for (int k = 0; k < 3; ++k) {
    const double a = (centre(k) - radius - origin_(k)) / cell_, b = (centre(k) + radius - origin_(k)) / cell_;
    if (!(b >= 0 && a <= dims_(k) - 1 + 1.0)) return;  // the box misses the grid (or NaN)
    lo(k) = static_cast<int>(std::max(0.0, std::floor(a)));
    hi(k) = static_cast<int>(std::min(static_cast<double>(dims_(k) - 1), std::floor(b)));
    if (hi(k) < lo(k)) return;
  }
  const double cells = (hi - lo + 1).cast<double>().prod();
  if (cells > count_) {
    for (int p = 0; p < count_; ++p) out.push_back(p);
    return;
  }
  for (int z = lo(2); z <= hi(2); ++z)
    for (int y = lo(1); y <= hi(1); ++y)
      for (int x = lo(0); x <= hi(0); ++x) {
        const size_t c = static_cast<size_t>((z * dims_(1) + y) * dims_(0) + x);
        for (int i = start_[c]; i < start_[c + 1]; ++i) out.push_back(points_[static_cast<size_t>(i)]);
      }
  std::sort(out.begin(), out.end());
}

}  // namespace tb
