#include "sweep_schedule.h"

#include <numeric>
#include <thread>

namespace tb::pbd {

std::vector<int> slab_owners(const Eigen::Matrix3Xd& at, const std::vector<double>& cost, int members) {
  const Eigen::Index n = at.cols();
  std::vector<int> owner(static_cast<size_t>(n), 0);
  if (n == 0 || members < 2) return owner;
  Eigen::Index axis = 0;
  (at.rowwise().maxCoeff() - at.rowwise().minCoeff()).maxCoeff(&axis);
  std::vector<int> order(static_cast<size_t>(n));
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return at(axis, a) < at(axis, b); });
  const double total = std::accumulate(cost.begin(), cost.end(), 0.0);
  double before = 0;
  for (int i : order) {
    const double c = cost[static_cast<size_t>(i)];
    // The slab of the item's middle: cost before it plus half its own.
    const double middle = total > 0 ? (before + c / 2) / total : 0;
    owner[static_cast<size_t>(i)] = std::min(members - 1, static_cast<int>(middle * members));
    before += c;
  }
  return owner;
}

int SweepSchedule::wait_for_others(int member, int need) const {
  for (unsigned spins = 1;; ++spins) {
    int least = classes_;
    for (int o = 0; o < members_; ++o)
      if (o != member) least = std::min(least, progress_[o].finished.load(std::memory_order_acquire));
    if (least >= need) return least;
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#endif
    // A member the host has descheduled (a 2-vCPU guest shares its cores) is let run.
    if ((spins & 4095) == 0) std::this_thread::yield();
  }
}

size_t SweepSchedule::waiting_items() const {
  size_t n = 0;
  for (const Member& m : by_member_)
    n += static_cast<size_t>(std::count_if(m.need.begin(), m.need.end(), [](int need) { return need >= 0; }));
  return n;
}

}  // namespace tb::pbd
