// MPI for the whole program: initialised once in main, with or without
// mpirun (a singleton run is one rank), finalised at exit. deal.II's
// MPI_InitFinalize underneath, one thread per rank (tb::use_one_thread stays in
// force on every rank).
#pragma once

#include <memory>
#include <vector>

namespace tb {

class MpiSession {
 public:
  MpiSession(int& argc, char**& argv);
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
  static int rank();  ///< in MPI_COMM_WORLD
  static int size();
  static void barrier();
  /// Peak resident memory of every rank in MiB (getrusage), rank by rank, on
  /// every rank. Collective.
  static std::vector<double> peak_memory_mib();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Peak resident memory of this process in MiB (getrusage ru_maxrss).
double peak_rss_mib();

}  // namespace tb
