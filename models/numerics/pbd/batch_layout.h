// The batches of one kind of PBD constraint: which constraint sits in which lane of
// which batch (colours, domain groups, vertex slots), and the numbers of each lane
// in one precision. Made by batch_packing.h, projected by a kind's batch kernels
// (batch_kernels.h), scheduled by batch_schedule.h.
#pragma once

#include <cstddef>
#include <vector>

#include "aligned_rows.h"
#include "constraints.h"

namespace tb::pbd {

/// What a projection may be told beyond its stiffness (each kind reads what
/// concerns it): the bending angle of eq. (19) or its signed form.
struct ProjectionOptions {
  BendingAngle bending_angle = BendingAngle::Unsigned;
};

/// Where each colour's batches start (begin.back() = batch count). A vertex of
/// valence beyond the colouring's 64 colours sends constraints to a last colour
/// (of its group) whose members may share vertices: in the interface group then
/// `last_shares_vertices`, and one thread sweeps it.
struct Colours {
  std::vector<size_t> begin;
  bool last_shares_vertices = false;
};

/// The batches of one kind of constraint: lanes in use per batch and the vertex
/// of each slot and lane; lanes at and beyond a batch's count are padding
/// (inverse masses 0, vertices of lane 0), computed but not written back.
struct BatchLayout {
  Colours colours;
  /// Where each group of colours starts (indices into colours.begin): groups
  /// 0 .. domains - 1 are the domains, the last the interface (everything when
  /// there is no partition); group_begin.back() = colour count.
  std::vector<size_t> group_begin;
  size_t domain_count() const { return group_begin.size() - 2; }
  std::vector<int> count;  ///< #batches
  std::vector<int> q;      ///< #batches by slots by width vertex indices
  size_t batch_count() const { return count.size(); }
};

/// The numbers of the batches of one kind in one precision: per batch, each
/// slot's inverse masses as the kind's kernel takes them (stretch: their shares
/// w_i / (w_1 + w_2)) and the rest values, lane by lane.
template <class S>
struct BatchNumbers {
  std::vector<S, AlignedAllocator<S>> w;     ///< #batches by slots by width
  std::vector<S, AlignedAllocator<S>> rest;  ///< #batches by rest values by width
};

/// The constraints of one kind whose corrections a sweep sums: those between a
/// pinned vertex of a group (a tool, the support) and free vertices. What such a
/// constraint adds to the free vertices' momentum, sum_j m_j dp_j (m_j the mass of
/// free slot j), is what the pinned vertex took from them: summed over a step's
/// sweeps and divided by h^2, the force on the group (pbd_solver.h,
/// Solver::group_forces). Each record r is a constraint row in a group, with its
/// slots' masses (0 for a pinned slot) and its running sum; the batched sweep
/// finds batch b's records in [batch_first[b], batch_first[b + 1]) at their lanes,
/// the scalar pass through of_row. Written by the one member that sweeps its batch.
struct CorrectionRecord {
  int arity = 0;
  std::vector<int> row, group, lane;  ///< per record
  std::vector<double> mass;           ///< per record, arity slots
  std::vector<int> batch_first;       ///< #batches + 1
  std::vector<int> of_row;            ///< per constraint row of the kind: its record, or -1
  std::vector<Vec3> sum;              ///< per record: sum over the sweeps of sum_j m_j dp_j
  bool empty() const { return row.empty(); }
  /// Record r's constraint moved its slots by corr(j) (j < arity): adds the momentum.
  template <class Corr>
  void add(int r, Corr&& corr) {
    for (int j = 0; j < arity; ++j) {
      const double m = mass[static_cast<size_t>(r * arity + j)];
      if (m != 0) sum[static_cast<size_t>(r)] += m * corr(j);
    }
  }
};

/// One kind's batches as a sweep projects them, in precision S.
template <class S>
struct KindSweep {
  const BatchLayout& layout;
  const BatchNumbers<S>& numbers;
  double stiffness;
  ProjectionOptions options;
  CorrectionRecord* record = nullptr;  ///< the corrections to sum, or null (none: the plain sweep)
};

}  // namespace tb::pbd
