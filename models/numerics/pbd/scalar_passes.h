// A kind's scalar Gauss-Seidel pass (constraint_kind.h ScalarPass): one
// constraint at a time in the batches' order, with the kind's reference
// projection (PBD, stiffness k) or its XPBD update (Macklin, Mueller, Chentanez
// 2016, eqs. 17-18: alpha~ and the multiplier lambda of each constraint).
// Compiled for each kind by define_constraint_kind.h.
#pragma once

#include <Eigen/Core>
#include <cstddef>

#include "aligned_rows.h"
#include "constraint_kind.h"

namespace tb::pbd {

template <class K, bool kXpbd>
void scalar_pass(const ScalarPass& a, bool reverse) {
  constexpr int N = K::kArity, R = K::kRestValues;
  auto P = [&a](int v) { return Eigen::Map<Vec3>(a.x + kPositionStride * Eigen::Index{a.row_of ? a.row_of[v] : v}); };
  const std::vector<int>& order = a.order;
  for (size_t k = 0; k < order.size(); ++k) {
    const int i = order[reverse ? order.size() - 1 - k : k];
    int q[N];
    Vec3 p[N], corr[N];
    double w[N], rest[R > 0 ? R : 1];
    for (int j = 0; j < N; ++j) {
      q[j] = a.constraints.vertices(i, j);
      p[j] = P(q[j]);
      w[j] = a.inverse_mass(q[j]);
    }
    for (int r = 0; r < R; ++r) rest[r] = a.constraints.rest(i, r);
    if constexpr (kXpbd)
      K::xpbd(p, w, rest, (*a.alpha_tilde)(i), (*a.lambda)(i), a.options, corr);
    else
      K::reference(p, w, rest, a.stiffness, a.options, corr);
    for (int j = 0; j < N; ++j) P(q[j]) += corr[j];
    if (a.record && a.record->of_row[static_cast<size_t>(i)] >= 0)
      a.record->add(a.record->of_row[static_cast<size_t>(i)], [&corr](int j) { return corr[j]; });
  }
}

}  // namespace tb::pbd
