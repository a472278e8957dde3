// A small persistent team of threads for the PBD sweep: the caller is
// member 0, the others wait for work, and members meet at a barrier between
// colours. OpenMP is not used: tb::use_one_thread() (models/numerics/elasticity/elastic_body.h)
// sets omp_set_max_active_levels(0) to keep CHOLMOD single-threaded, which
// disables every OpenMP parallel region in the process; and a sweep needs a
// barrier per colour, several hundred per frame, where a spin barrier costs a
// fraction of a microsecond (benchmark BM_ThreadTeamBarrier).
// Waiting members spin for a while, then sleep on a futex, so an idle team costs
// no CPU between frames. A task must not allocate, throw or call run() itself.
#pragma once

#include <atomic>
#include <thread>
#include <vector>

namespace tb::pbd {

class ThreadTeam {
 public:
  /// `size` members: the caller of run() and size - 1 threads started here.
  explicit ThreadTeam(int size);
  ~ThreadTeam();
  ThreadTeam(const ThreadTeam&) = delete;
  ThreadTeam& operator=(const ThreadTeam&) = delete;

  int size() const { return size_; }

  /// Runs task(member) on every member in [0, size()), the caller as member 0,
  /// and returns when all have finished. No heap allocation.
  template <class Task>
  void run(Task& task) {
    run_erased(&task, [](void* t, int member) { (*static_cast<Task*>(t))(member); });
  }

  /// Returns when every member has called barrier() (from inside a task).
  void barrier();

 private:
  using Erased = void (*)(void*, int);
  void run_erased(void* task, Erased call);
  void work(int member);
  /// Waits until `word` differs from `seen`: spins, then sleeps on the futex
  /// (counted in `sleepers`, so that advance() makes a system call only when
  /// someone sleeps).
  static void wait_while_equal(const std::atomic<unsigned>& word, unsigned seen, std::atomic<int>& sleepers);
  static void advance(std::atomic<unsigned>& word, std::atomic<int>& sleepers);

  int size_;
  std::vector<std::thread> threads_;
  // Work hand-out: a new epoch starts a task on every waiting member.
  alignas(64) std::atomic<unsigned> epoch_{0};
  std::atomic<int> epoch_sleepers_{0};
  void* task_ = nullptr;
  Erased call_ = nullptr;
  bool stop_ = false;
  // Barrier: arrivals counted, the last one advances the generation.
  alignas(64) std::atomic<int> arrived_{0};
  alignas(64) std::atomic<unsigned> generation_{0};
  std::atomic<int> generation_sleepers_{0};
};

}  // namespace tb::pbd
