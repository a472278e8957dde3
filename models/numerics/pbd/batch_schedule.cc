#include "batch_schedule.h"

#include <cstddef>

namespace tb::pbd {
namespace {

/// A colour with fewer batches than this per member is swept by member 0 alone:
/// splitting it would cost more in barriers and idle members than it saves (the
/// greedy colouring leaves a tail of small colours: at 10k vertices the last
/// bending colours hold 122, 50, 21, 13, 7, 4 and 1 batches of eight).
constexpr size_t kMinBatchesPerMember = 16;

/// One kind's batches in one sweep, with the kernel that projects a range of them.
template <class S>
struct KindPass {
  const BatchLayout& layout;
  KindSweep<S> batches;
  typename BatchKernels<S>::Sweep project;
  S* x;
  ThreadTeam* team;
  void sweep(size_t begin, size_t end, bool reverse) const { project(x, batches, begin, end, reverse); }
};

/// One member's part of a sweep over the interface group of one kind of
/// constraint (everything, with no domains): of each colour (in order, or
/// reversed), its share of the batches, then a barrier. A colour whose
/// constraints may share vertices, or a small one, is swept by member 0 alone, and
/// consecutive such colours need no barrier between them (one thread, in order).
/// Who sweeps what never changes the result: within a colour the constraints are
/// independent, and colours follow each other in order.
template <class S>
void sweep_colours(const KindPass<S>& a, bool reverse, int member, int members) {
  const BatchLayout& layout = a.layout;
  const size_t first = layout.group_begin[layout.domain_count()], colour_end = layout.group_begin.back();
  const size_t colour_count = colour_end - first;
  auto size = [&](size_t colour) { return layout.colours.begin[colour + 1] - layout.colours.begin[colour]; };
  auto alone = [&](size_t colour) {
    return members == 1 || (layout.colours.last_shares_vertices && colour == colour_end - 1) ||
           size(colour) < kMinBatchesPerMember * static_cast<size_t>(members);
  };
  for (size_t c = 0; c < colour_count; ++c) {
    const size_t colour = first + (reverse ? colour_count - 1 - c : c);
    const size_t begin = layout.colours.begin[colour], count = size(colour);
    const bool by_one = alone(colour);
    const size_t from = by_one ? (member == 0 ? 0 : count) : count * static_cast<size_t>(member) / members,
                 to = by_one ? count : count * static_cast<size_t>(member + 1) / members;
    a.sweep(begin + from, begin + to, reverse);
    // The next colour may start when every member is done with this one, unless
    // member 0 sweeps both (the next kind of constraint or sweep: always a barrier).
    const bool last = c + 1 == colour_count;
    const size_t next = reverse ? colour - 1 : colour + 1;
    if (members > 1 && (last || !by_one || !alone(next))) a.team->barrier();
  }
}

/// One member's part of a sweep over the domains of one kind of constraint:
/// domains member, member + members, ..., each whole (its batches in order, or
/// reversed), then a barrier. Domains share no vertex, so who sweeps which does
/// not change the result.
template <class S>
void sweep_domains(const KindPass<S>& a, bool reverse, int member, int members) {
  const BatchLayout& layout = a.layout;
  const size_t domains = layout.domain_count();
  for (size_t d = static_cast<size_t>(member); d < domains; d += static_cast<size_t>(members))
    a.sweep(layout.colours.begin[layout.group_begin[d]], layout.colours.begin[layout.group_begin[d + 1]], reverse);
  if (members > 1) a.team->barrier();
}

/// One member's part of a sweep over one kind of constraint in the batches'
/// order (domains, then the interface), or reversed.
template <class S>
void sweep_kind(const KindPass<S>& a, bool reverse, int member, int members) {
  const bool domains = a.layout.domain_count() > 0;
  if (domains && !reverse) sweep_domains(a, reverse, member, members);
  sweep_colours(a, reverse, member, members);
  if (domains && reverse) sweep_domains(a, reverse, member, members);
}

/// Member `member`'s part of every sweep.
template <class S>
void member_sweeps(const SweepPlan<S>& plan, int member) {
  const int members = plan.team ? plan.team->size() : 1;
  for (int it = 0; it < plan.iterations; ++it) {
    const bool reverse = plan.first_reverse != (it % 2 == 1);
    for (size_t k = 0; k < plan.kinds.size(); ++k) {
      if (!(plan.stiffness[k] > 0)) continue;
      const KindBatches& kind = plan.kinds[k];
      CorrectionRecord* record = plan.records && !(*plan.records)[k].empty() ? &(*plan.records)[k] : nullptr;
      const KindPass<S> pass{kind.layout,
                             {kind.layout, kind.numbers<S>(), plan.stiffness[k], plan.options, record},
                             kind.kind->kernels<S>().sweep[index(plan.isa)],
                             plan.x,
                             plan.team};
      sweep_kind(pass, reverse, member, members);
    }
  }
}

}  // namespace

template <class S>
void run_sweeps(const SweepPlan<S>& plan) {
  auto sweeps = [&plan](int member) { member_sweeps(plan, member); };
  if (plan.team)
    plan.team->run(sweeps);
  else
    sweeps(0);
}

template void run_sweeps(const SweepPlan<double>&);
template void run_sweeps(const SweepPlan<float>&);

}  // namespace tb::pbd
