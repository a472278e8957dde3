// Who sweeps which batches when: the Gauss-Seidel sweeps over every kind's batches
// (batch_packing.h) in the table's order, alternately forward and reverse, shared
// out between the members of a thread team (thread_team.h): each domain swept whole
// by one member, then each interface colour's batches split between them, with a
// barrier wherever one member's writes must be seen by the next step. Because the
// constraints of a colour are independent and domains share no vertex, the result
// is bitwise the same for any team size.
#pragma once

#include <vector>

#include "batch_packing.h"
#include "instruction_set.h"
#include "thread_team.h"

namespace tb::pbd {

/// What the sweeps of one projection need; `team` may be null (this thread alone).
template <class S>
struct SweepPlan {
  const std::vector<KindBatches>& kinds;  ///< in the table's order
  const std::vector<double>& stiffness;   ///< one per kind; a kind with stiffness <= 0 is not swept
  ProjectionOptions options;
  InstructionSet isa;  ///< the kinds' kernels for it (BatchKernels), picked once per kind and sweep
  S* x;                ///< positions, kPositionStride numbers per vertex
  int iterations;
  bool first_reverse;
  ThreadTeam* team;
  /// One per kind, the corrections to sum (batch_layout.h), or null: none.
  std::vector<CorrectionRecord>* records = nullptr;
};

/// `iterations` sweeps, the first forward (or reverse), then alternating; each
/// sweep projects every kind with stiffness > 0 in turn, whole.
template <class S>
void run_sweeps(const SweepPlan<S>& plan);

}  // namespace tb::pbd
