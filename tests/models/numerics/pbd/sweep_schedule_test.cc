// The barrier-free sweep (models/numerics/parallel/sweep_schedule.h) on a synthetic
// Gauss-Seidel: items that each read and rewrite a few shared values, coloured so
// that no two of a class share one. Run by teams of 2-4 members, with the items in
// slabs, strewn or lopsided over the members and of uneven cost (so members drift
// apart between classes), it must give the bits of one thread running the classes in
// order, every time.
// slab_owners, which gives a mesh's members their regions, cuts equal costs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <random>
#include <vector>

#include "sweep_schedule.h"
#include "thread_team.h"

namespace tb::pbd {
namespace {

struct SyntheticSweep {
  int keys = 600;
  std::vector<std::vector<int>> item_keys;  ///< per item, 2-5 distinct keys
  std::vector<std::vector<int>> classes;    ///< greedy: no two items of a class share a key

  SyntheticSweep() {
    std::mt19937 random(7);
    std::uniform_int_distribution<int> key(0, keys - 1), count(2, 5);
    for (int i = 0; i < 3000; ++i) {
      std::vector<int> k;
      // Mostly near the item's own place (as a mesh's neighbours are), some far.
      const int home = i * keys / 3000;
      for (int c = count(random); static_cast<int>(k.size()) < c;) {
        const int candidate = random() % 4 == 0 ? key(random) : (home + key(random) % 9) % keys;
        if (std::find(k.begin(), k.end(), candidate) == k.end()) k.push_back(candidate);
      }
      item_keys.push_back(k);
    }
    std::vector<std::vector<int>> taken(static_cast<size_t>(keys));
    for (int i = 0; i < static_cast<int>(item_keys.size()); ++i) {
      auto free = [&](int c) {
        for (int k : item_keys[static_cast<size_t>(i)])
          if (std::count(taken[static_cast<size_t>(k)].begin(), taken[static_cast<size_t>(k)].end(), c)) return false;
        return true;
      };
      int c = 0;
      while (!free(c)) ++c;
      if (c >= static_cast<int>(classes.size())) classes.resize(static_cast<size_t>(c) + 1);
      classes[static_cast<size_t>(c)].push_back(i);
      for (int k : item_keys[static_cast<size_t>(i)]) taken[static_cast<size_t>(k)].push_back(c);
    }
  }

  /// Item i: reads its keys' values and rewrites each from all of them; every
  /// seventh item also does some unrelated work, so members run at uneven pace.
  void item(std::vector<double>& values, int i) const {
    const std::vector<int>& k = item_keys[static_cast<size_t>(i)];
    double sum = 0;
    for (int key : k) sum += values[static_cast<size_t>(key)];
    if (i % 7 == 0) {
      volatile double spin = sum;
      for (int r = 0; r < 200; ++r) spin = std::sin(spin) + 1e-3 * r;
    }
    for (size_t a = 0; a < k.size(); ++a)
      values[static_cast<size_t>(k[a])] = std::cos(sum + static_cast<double>(a)) + 0.5 * values[static_cast<size_t>(k[a])];
  }

  /// Who runs item i: slabs of the items' order (as slab_owners gives a mesh), or
  /// every member's items strewn over all of them (the most dependences), or one
  /// member with most of the work.
  int owner(int i, int members, int how) const {
    const int n = static_cast<int>(item_keys.size());
    if (how == 0) return i * members / n;
    if (how == 1) return i % members;
    return i < n * 7 / 10 ? 0 : 1 + i % (members - 1);
  }
};

TEST(SweepSchedule, ATeamWithoutBarriersGivesTheBitsOfOneThreadInClassOrder) {
  const SyntheticSweep s;
  ASSERT_GT(s.classes.size(), 5u);
  std::vector<double> start(static_cast<size_t>(s.keys));
  for (size_t k = 0; k < start.size(); ++k) start[k] = std::sin(static_cast<double>(k));
  std::vector<double> one = start;
  for (int sweep = 0; sweep < 3; ++sweep)
    for (const std::vector<int>& c : s.classes)
      for (int i : c) s.item(one, i);

  for (int members : {2, 3, 4})
    for (int how : {0, 1, 2}) {
      ThreadTeam team(members);
      SweepSchedule schedule(
          s.classes, members, [&](int i) { return s.owner(i, members, how); }, s.keys,
          [&](int i, std::vector<int>& keys) {
            const auto& k = s.item_keys[static_cast<size_t>(i)];
            keys.insert(keys.end(), k.begin(), k.end());
          });
      EXPECT_EQ(schedule.members(), members);
      EXPECT_GT(schedule.waiting_items(), 0u);
      EXPECT_LT(schedule.waiting_items(), s.item_keys.size());
      for (int repeat = 0; repeat < 20; ++repeat) {
        std::vector<double> many = start;
        auto item = [&](int i) { s.item(many, i); };
        for (int sweep = 0; sweep < 3; ++sweep) schedule.run(team, item);
        ASSERT_EQ(many, one) << members << " members, owners " << how << ", repeat " << repeat;
      }
    }
}

TEST(SweepSchedule, RefusesATeamOfAnotherSizeAndAnOwnerOutsideTheTeam) {
  const SyntheticSweep s;
  auto keys = [&](int i, std::vector<int>& out) {
    out.insert(out.end(), s.item_keys[static_cast<size_t>(i)].begin(), s.item_keys[static_cast<size_t>(i)].end());
  };
  SweepSchedule schedule(s.classes, 2, [&](int i) { return s.owner(i, 2, 0); }, s.keys, keys);
  ThreadTeam three(3);
  auto nothing = [](int) {};
  EXPECT_THROW(schedule.run(three, nothing), std::logic_error);
  EXPECT_THROW(SweepSchedule(s.classes, 2, [](int) { return 2; }, s.keys, keys), std::invalid_argument);
}

// Slabs along the axis the places spread most, of equal cost, the same every time.
TEST(SweepSchedule, SlabOwnersCutAlongTheLongestAxisIntoEqualCost) {
  const int n = 1000;
  Eigen::Matrix3Xd at(3, n);
  std::vector<double> cost(n);
  std::mt19937 random(3);
  std::uniform_real_distribution<double> u(0, 1);
  for (int i = 0; i < n; ++i) {
    at.col(i) << u(random), 5 * u(random), u(random);  // spread most along y
    cost[static_cast<size_t>(i)] = 1 + (i % 5);
  }
  for (int members : {1, 2, 3}) {
    const std::vector<int> owner = slab_owners(at, cost, members);
    EXPECT_EQ(owner, slab_owners(at, cost, members));
    std::vector<double> part(static_cast<size_t>(members), 0), low(static_cast<size_t>(members), 1e9),
        high(static_cast<size_t>(members), -1e9);
    for (int i = 0; i < n; ++i) {
      const size_t m = static_cast<size_t>(owner[static_cast<size_t>(i)]);
      part[m] += cost[static_cast<size_t>(i)];
      low[m] = std::min(low[m], at(1, i));
      high[m] = std::max(high[m], at(1, i));
    }
    const double total = std::accumulate(cost.begin(), cost.end(), 0.0);
    for (int m = 0; m < members; ++m) {
      EXPECT_NEAR(part[static_cast<size_t>(m)], total / members, 5) << members << " members";
      if (m > 0) {
        EXPECT_LE(high[static_cast<size_t>(m) - 1], low[static_cast<size_t>(m)]) << "slabs along y, in order";
      }
    }
  }
}

}  // namespace
}  // namespace tb::pbd
