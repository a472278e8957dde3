// MPI for the whole program: initialised once in main, with or without
// mpirun (a singleton run is one rank), finalised at exit. deal.II's
// MPI_InitFinalize underneath, one thread per rank (tb::use_one_thread stays in
// force on every rank).
#pragma once

#include <memory>
#include <string>
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
  /// Every rank's `mine`, rank by rank, on every rank. Collective.
  static std::vector<double> all_gather(double mine);
  /// Every rank's `mine`, rank by rank, on rank 0 (empty on the others). Collective.
  static std::vector<std::string> gather_to_root(const std::string& mine);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tb
