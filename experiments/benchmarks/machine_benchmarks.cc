// What the machine's two hardware threads can do together, to read the models'
// two-thread speed-ups against: each member of a thread team runs the same
// private arithmetic kernel, so two members on two physical cores finish in the
// time of one (combined rate 2x), and two hyper-threads of one core share its
// execution ports: a kernel that keeps the ports busy runs at the rate of one,
// a kernel that waits on its own latency still doubles. A guest's "2 cores" may
// be either (lscpu inside a VM reports what the hypervisor says, not what it
// maps); this measures it. docs/realtime_nonlinear.md reads the XPBD and VBD
// sweeps' speed-ups against it.
#include <benchmark/benchmark.h>

#include <array>
#include <cmath>

#include "thread_team.h"

namespace tb {
namespace {

constexpr long kOperations = 4'000'000;  ///< per member and iteration

/// One dependent chain of multiply-adds: every operation waits for the one before
/// (about 8 cycles of latency each), so one thread leaves most ports idle.
double latency_kernel(double seed) {
  double x = seed;
  for (long i = 0; i < kOperations; ++i) x = x * 0.999999 + 1e-7;
  return x;
}

/// Sixteen independent chains of the same multiply-adds, interleaved: one thread
/// alone keeps the floating-point ports busy.
double throughput_kernel(double seed) {
  std::array<double, 16> x;
  for (size_t k = 0; k < x.size(); ++k) x[k] = seed + static_cast<double>(k);
  for (long i = 0; i < kOperations / 16; ++i)
    for (double& v : x) v = v * 0.999999 + 1e-7;
  double sum = 0;
  for (double v : x) sum += v;
  return sum;
}

/// Four independent chains of a square root and a division (the long-latency
/// operations of the XPBD tet projection, xpbd_tet_solve.cc): bound by the
/// core's divider, which hyper-threads share.
double divide_kernel(double seed) {
  std::array<double, 4> x;
  for (size_t k = 0; k < x.size(); ++k) x[k] = seed + static_cast<double>(k);
  for (long i = 0; i < kOperations / 4; ++i)
    for (double& v : x) v = 1.0 + 1.0 / (std::sqrt(v) + 1.0);
  return x[0] + x[1] + x[2] + x[3];
}

/// range(0): the kernel (0 latency-bound, 1 port-bound multiply-add, 2 divide and
/// square root); range(1): members, each running the kernel once per iteration.
/// Counter gops: the members' operations together, 10^9 a second of wall time; the
/// two-member row over the one-member row is what two threads can gain on it.
void BM_CoreSharing(benchmark::State& state) {
  const int kind = static_cast<int>(state.range(0));
  pbd::ThreadTeam team(static_cast<int>(state.range(1)));
  std::array<double, 8> sink{};
  auto task = [&](int member) {
    const double seed = 1.0 + member;
    sink[static_cast<size_t>(member)] =
        kind == 0 ? latency_kernel(seed) : kind == 1 ? throughput_kernel(seed) : divide_kernel(seed);
  };
  for (auto _ : state) {
    team.run(task);
    benchmark::DoNotOptimize(sink);
  }
  state.counters["gops"] = benchmark::Counter(static_cast<double>(kOperations) * team.size() * 1e-9,
                                                    benchmark::Counter::kIsIterationInvariantRate);
}

BENCHMARK(BM_CoreSharing)
    ->ArgNames({"kind", "members"})
    ->ArgsProduct({{0, 1, 2}, {1, 2}})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace tb
