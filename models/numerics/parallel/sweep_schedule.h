// A Gauss-Seidel sweep over colour classes run by a thread team without a barrier
// between classes. With a barrier, every member waits at the end of each class for
// the slowest one, and the per-class spread of the members' halves adds up over the
// 30-40 classes of a tet mesh's colouring (docs/realtime_nonlinear.md, "Where XPBD's
// two threads wait on the paper cube"). Here a member waits only where it must: before
// an item that shares data with an item another member runs in an earlier class, until
// that member has finished that class (point-to-point synchronisation on per-member
// progress counters; the same dependence a barrier enforces, kept for the pairs that
// have one). Within a member's share of a class the items that wait on nothing (or on
// an earlier class) come first; the items of a class touch disjoint data, so their
// order does not change the result: the sweep gives the same bits as one thread
// running the classes in order.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <atomic>
#include <cstddef>
#include <memory>
#include <stdexcept>
#include <vector>

#include "thread_team.h"

namespace tb::pbd {

/// The member that runs each item: slabs across the axis along which the items'
/// places spread most (`at`, column i: item i's place), each slab holding about an
/// equal part of the summed `cost` (cost[i] >= 0: item i's). Two members then depend
/// on each other only across a slab's faces, in every class alike. Deterministic
/// (ties in item order).
std::vector<int> slab_owners(const Eigen::Matrix3Xd& at, const std::vector<double>& cost, int members);

class SweepSchedule {
 public:
  /// `classes`: the items of each class (two items of one class share no key);
  /// `owner(item)`: the member in [0, members) that runs it (best the same region of
  /// the body in every class, so that members depend on each other only where their
  /// regions meet: slab_owners); `keys(item, out)` appends to `out` the keys of the
  /// data the item reads or writes, each in [0, key_count), where two items that
  /// share a key must run in class order (a node both write, a tet both read).
  template <class Owner, class Keys>
  SweepSchedule(const std::vector<std::vector<int>>& classes, int members, Owner&& owner, int key_count, Keys&& keys);

  int members() const { return members_; }

  /// Runs item(k) for every item of every class on `team` (of members() members):
  /// the result of running the classes one after the other. No heap allocation.
  template <class Item>
  void run(ThreadTeam& team, Item& item);

  /// How many items depend on another member's earlier class (each may wait for it).
  size_t waiting_items() const;

 private:
  struct Member {
    std::vector<int> items;          ///< in the order this member runs them
    std::vector<int> need;           ///< per item: the class each other member must have finished first (-1: none)
    std::vector<size_t> class_end;   ///< per class: the end of its items in `items`
  };
  struct alignas(64) Progress {
    std::atomic<int> finished{-1};  ///< the last class this member has finished
  };

  /// Waits until every member but `member` has finished class `need`; returns the
  /// smallest class they have all finished.
  int wait_for_others(int member, int need) const;

  int members_ = 1;
  int classes_ = 0;
  std::vector<Member> by_member_;
  std::unique_ptr<Progress[]> progress_;
};

template <class Owner, class Keys>
SweepSchedule::SweepSchedule(const std::vector<std::vector<int>>& classes, int members, Owner&& owner, int key_count,
                             Keys&& keys)
    : members_(members),
      classes_(static_cast<int>(classes.size())),
      by_member_(static_cast<size_t>(members)),
      progress_(new Progress[static_cast<size_t>(members)]) {
  if (members < 1) throw std::invalid_argument("sweep schedule: at least one member");
  const size_t team = static_cast<size_t>(members);
  // The last class in which each member touched each key so far (-1: never).
  std::vector<int> last(static_cast<size_t>(key_count) * team, -1);
  std::vector<int> item_keys;
  std::vector<std::vector<std::pair<int, int>>> shares(team);  // per member: (need, item)
  for (size_t c = 0; c < classes.size(); ++c) {
    for (auto& share : shares) share.clear();
    for (int item : classes[c]) {
      const int m = owner(item);
      if (m < 0 || m >= members) throw std::invalid_argument("sweep schedule: an item's owner is not a member");
      item_keys.clear();
      keys(item, item_keys);
      int need = -1;
      for (int key : item_keys)
        for (size_t o = 0; o < team; ++o)
          if (o != static_cast<size_t>(m)) need = std::max(need, last[static_cast<size_t>(key) * team + o]);
      shares[static_cast<size_t>(m)].emplace_back(need, item);
    }
    for (size_t m = 0; m < team; ++m) {
      // The items that wait on nothing, or on the earliest classes, first.
      std::stable_sort(shares[m].begin(), shares[m].end(),
                       [](const auto& a, const auto& b) { return a.first < b.first; });
      Member& mine = by_member_[m];
      for (const auto& [need, item] : shares[m]) {
        mine.items.push_back(item);
        mine.need.push_back(need);
      }
      mine.class_end.push_back(mine.items.size());
    }
    // Only now: the items of class c share no key, so none waits on another of c.
    for (int item : classes[c]) {
      item_keys.clear();
      keys(item, item_keys);
      for (int key : item_keys) last[static_cast<size_t>(key) * team + static_cast<size_t>(owner(item))] = static_cast<int>(c);
    }
  }
}

template <class Item>
void SweepSchedule::run(ThreadTeam& team, Item& item) {
  if (team.size() != members_) throw std::logic_error("sweep schedule: made for another team size");
  for (int m = 0; m < members_; ++m) progress_[m].finished.store(-1, std::memory_order_relaxed);
  // run() hands the task out with a release and each member starts with an acquire,
  // so every member sees the counters reset.
  auto task = [&](int member) {
    const Member& mine = by_member_[static_cast<size_t>(member)];
    int seen = -1;  // every other member has finished at least this class
    size_t k = 0;
    for (int c = 0; c < classes_; ++c) {
      const size_t end = mine.class_end[static_cast<size_t>(c)];
      for (; k < end; ++k) {
        const int need = mine.need[k];
        if (need > seen) seen = wait_for_others(member, need);
        item(mine.items[k]);
      }
      progress_[member].finished.store(c, std::memory_order_release);
    }
  };
  team.run(task);
}

}  // namespace tb::pbd
