#include "domain_partition.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>

namespace tb::pbd {
namespace {

/// Splits vertices [begin, end) of `order` into `parts` domains numbered from `first`.
void bisect(const Points& x, const std::vector<double>& work, std::vector<int>& order, size_t begin, size_t end,
            int parts, int first, std::vector<int>& domain) {
  if (parts == 1) {
    for (size_t i = begin; i < end; ++i) domain[static_cast<size_t>(order[i])] = first;
    return;
  }
  auto box = [&](bool working_only) {
    Eigen::RowVector3d lo = Eigen::RowVector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (size_t i = begin; i < end; ++i)
      if (!working_only || work[static_cast<size_t>(order[i])] > 0) {
        lo = lo.cwiseMin(x.row(order[i]));
        hi = hi.cwiseMax(x.row(order[i]));
      }
    return Eigen::RowVector3d(hi - lo);
  };
  Eigen::RowVector3d extent = box(true);
  if (!(extent.minCoeff() >= 0)) extent = box(false);  // no vertex with work here
  Eigen::Index axis = 0;
  extent.maxCoeff(&axis);
  std::sort(order.begin() + static_cast<std::ptrdiff_t>(begin), order.begin() + static_cast<std::ptrdiff_t>(end),
            [&](int a, int b) { return x(a, axis) < x(b, axis) || (x(a, axis) == x(b, axis) && a < b); });
  // Proportional shares: `left` of the `parts` domains take that share of the
  // work, so the split is the first vertex where the running work reaches it
  // (with unit work, left / parts of the vertices, rounded down).
  const int left = parts / 2;
  double total = 0;
  for (size_t i = begin; i < end; ++i) total += work[static_cast<size_t>(order[i])];
  size_t middle = begin + (end - begin) * static_cast<size_t>(left) / static_cast<size_t>(parts);
  if (total > 0) {
    const double share = std::floor(total * left / parts);
    double running = 0;
    middle = begin;
    while (middle < end && running < share) running += work[static_cast<size_t>(order[middle++])];
  }
  bisect(x, work, order, begin, middle, left, first, domain);
  bisect(x, work, order, middle, end, parts - left, first + left, domain);
}

}  // namespace

std::vector<int> bisect_into_domains(const Points& positions, int domains, const std::vector<double>& work) {
  if (domains < 1) throw std::invalid_argument("PBD domains: at least one, not " + std::to_string(domains));
  const size_t n = static_cast<size_t>(positions.rows());
  if (!work.empty() && work.size() != n)
    throw std::invalid_argument("PBD domains: " + std::to_string(work.size()) + " work weights for " +
                                std::to_string(n) + " vertices");
  for (double w : work)
    if (!(w >= 0) || !std::isfinite(w))
      throw std::invalid_argument("PBD domains: work weights must be finite and >= 0");
  std::vector<int> domain(n, 0);
  if (domains == 1 || n == 0) return domain;
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  bisect(positions, work.empty() ? std::vector<double>(n, 1.0) : work, order, 0, n, domains, 0, domain);
  return domain;
}

}  // namespace tb::pbd
