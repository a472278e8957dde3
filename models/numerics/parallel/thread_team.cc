#include "thread_team.h"

#include <linux/futex.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <chrono>
#include <climits>
#include <stdexcept>

namespace tb::pbd {
namespace {

/// How long a waiting member spins before it sleeps: longer than a colour's work
/// and than the serial part of a frame (so neither a barrier nor the next run of
/// back-to-back frames finds it asleep), short enough that an idle team leaves the
/// CPU to others between frames at 60 Hz. Waking a sleeping member is a futex
/// system call that, in the 2-vCPU VM of docs/realtime_nonlinear.md, took about a
/// tenth of the caller's time in a one-sweep VBD frame at the 50 us this was
/// before (perf, "Two threads and the serial remainder"). OpenMP runtimes spin
/// longer by default (libgomp's GOMP_SPINCOUNT of 300 000 pauses, Intel's
/// KMP_BLOCKTIME of 200 ms).
constexpr auto kSpin = std::chrono::milliseconds(1);

inline void cpu_relax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#endif
}

long futex(const std::atomic<unsigned>& word, int op, unsigned value) {
  static_assert(sizeof(std::atomic<unsigned>) == sizeof(unsigned), "futex on the atomic's storage");
  return syscall(SYS_futex, reinterpret_cast<const unsigned*>(&word), op, value, nullptr, nullptr, 0);
}

}  // namespace

ThreadTeam::ThreadTeam(int size) : size_(size) {
  if (size < 1) throw std::invalid_argument("thread team: at least one member");
  threads_.reserve(static_cast<size_t>(size - 1));
  for (int m = 1; m < size; ++m) threads_.emplace_back([this, m] { work(m); });
}

ThreadTeam::~ThreadTeam() {
  stop_ = true;
  advance(epoch_, epoch_sleepers_);
  for (std::thread& t : threads_) t.join();
}

void ThreadTeam::wait_while_equal(const std::atomic<unsigned>& word, unsigned seen, std::atomic<int>& sleepers) {
  const auto start = std::chrono::steady_clock::now();
  for (int spins = 0; word.load(std::memory_order_acquire) == seen; ++spins) {
    cpu_relax();
    if ((spins & 255) == 255 && std::chrono::steady_clock::now() - start > kSpin) {
      // Sequentially consistent with advance(): either it sees this sleeper and
      // wakes it, or this load sees its new value (the futex rechecks the word).
      sleepers.fetch_add(1);
      while (word.load() == seen) futex(word, FUTEX_WAIT_PRIVATE, seen);
      sleepers.fetch_sub(1);
      return;
    }
  }
}

void ThreadTeam::advance(std::atomic<unsigned>& word, std::atomic<int>& sleepers) {
  word.fetch_add(1);
  if (sleepers.load() > 0) futex(word, FUTEX_WAKE_PRIVATE, INT_MAX);
}

void ThreadTeam::barrier() {
  if (size_ == 1) return;
  const unsigned generation = generation_.load(std::memory_order_acquire);
  if (arrived_.fetch_add(1, std::memory_order_acq_rel) == size_ - 1) {
    arrived_.store(0, std::memory_order_relaxed);
    advance(generation_, generation_sleepers_);
  } else {
    wait_while_equal(generation_, generation, generation_sleepers_);
  }
}

void ThreadTeam::run_erased(void* task, Erased call) {
  if (size_ == 1) {
    call(task, 0);
    return;
  }
  task_ = task;
  call_ = call;
  advance(epoch_, epoch_sleepers_);
  call(task, 0);
  barrier();  // every member has finished its part
}

void ThreadTeam::work(int member) {
  unsigned seen = 0;
  for (;;) {
    wait_while_equal(epoch_, seen, epoch_sleepers_);
    seen = epoch_.load(std::memory_order_acquire);
    if (stop_) return;
    call_(task_, member);
    barrier();
  }
}

}  // namespace tb::pbd
