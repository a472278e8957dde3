// Which constraint goes into which batch: the constraints of one kind that can
// move something, ordered by a greedy graph colouring (no two constraints of one
// colour share a vertex), domain by domain when the surface is partitioned
// (domain_partition.h), and packed into batches of independent constraints, one
// per lane, with their numbers in the sweep's precision. Setup only.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "batch_layout.h"
#include "constraint_kind.h"
#include "instruction_set.h"

namespace tb::pbd {

/// The batches of one kind, ready to sweep.
struct KindBatches {
  const ConstraintKind* kind;
  std::vector<int> order;  ///< the order of projection (forward): rows of the kind's constraints
  BatchLayout layout;
  BatchNumbers<double> double_numbers;  ///< filled in double precision
  BatchNumbers<float> single_numbers;   ///< filled in single precision
  Eigen::Index rows;                    ///< constraints of the kind, kept or not

  template <class S>
  const BatchNumbers<S>& numbers() const {
    return for_precision<S>(double_numbers, single_numbers);
  }
};

/// Keeps the constraints that can move something (one of their vertices has
/// inverse mass > 0), orders them by a greedy graph colouring and packs
/// consecutive independent ones into batches of `width` lanes (batch_width) with
/// their numbers in `precision`. With `vertex_domain`, the order is domain 0's
/// constraints (those with every vertex in domain 0) coloured, then domain 1's,
/// ..., then the interface's (the rest) coloured.
///   inverse_mass   #V
///   vertex_domain  #V domain indices in [0, domains), or empty: one group
KindBatches pack_kind(const KindConstraints& constraints, const Eigen::VectorXd& inverse_mass, int width,
                      Precision precision, const std::vector<int>& vertex_domain, int domains);

}  // namespace tb::pbd
