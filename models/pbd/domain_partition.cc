#include "domain_partition.h"

#include <algorithm>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>

namespace tb::pbd {
namespace {

/// Splits vertices [begin, end) of `order` into `parts` domains numbered from `first`.
void bisect(const Points& x, std::vector<int>& order, size_t begin, size_t end, int parts, int first,
            std::vector<int>& domain) {
  if (parts == 1) {
    for (size_t i = begin; i < end; ++i) domain[static_cast<size_t>(order[i])] = first;
    return;
  }
  Eigen::RowVector3d lo = Eigen::RowVector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (size_t i = begin; i < end; ++i) {
    lo = lo.cwiseMin(x.row(order[i]));
    hi = hi.cwiseMax(x.row(order[i]));
  }
  Eigen::Index axis = 0;
  (hi - lo).maxCoeff(&axis);
  std::sort(order.begin() + static_cast<std::ptrdiff_t>(begin), order.begin() + static_cast<std::ptrdiff_t>(end),
            [&](int a, int b) { return x(a, axis) < x(b, axis) || (x(a, axis) == x(b, axis) && a < b); });
  // Proportional sizes: `left` of the `parts` domains take that share of the vertices.
  const int left = parts / 2;
  const size_t middle = begin + (end - begin) * static_cast<size_t>(left) / static_cast<size_t>(parts);
  bisect(x, order, begin, middle, left, first, domain);
  bisect(x, order, middle, end, parts - left, first + left, domain);
}

}  // namespace

std::vector<int> bisect_into_domains(const Points& positions, int domains) {
  if (domains < 1) throw std::invalid_argument("PBD domains: at least one, not " + std::to_string(domains));
  const size_t n = static_cast<size_t>(positions.rows());
  std::vector<int> domain(n, 0);
  if (domains == 1 || n == 0) return domain;
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  bisect(positions, order, 0, n, domains, 0, domain);
  return domain;
}

}  // namespace tb::pbd
