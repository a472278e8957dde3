#include "mpi_session.h"

#include <deal.II/base/mpi.h>
#include <mpi.h>
#include <sys/resource.h>

namespace tb {

struct MpiSession::Impl {
  dealii::Utilities::MPI::MPI_InitFinalize init;
  Impl(int& argc, char**& argv) : init(argc, argv, 1) {}
};

MpiSession::MpiSession(int& argc, char**& argv) : impl_(std::make_unique<Impl>(argc, argv)) {}
MpiSession::~MpiSession() = default;

int MpiSession::rank() {
  int r = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}

int MpiSession::size() {
  int s = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &s);
  return s;
}

void MpiSession::barrier() { MPI_Barrier(MPI_COMM_WORLD); }

double peak_rss_mib() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

std::vector<double> MpiSession::peak_memory_mib() {
  double mine = peak_rss_mib();
  std::vector<double> all(static_cast<size_t>(size()));
  MPI_Allgather(&mine, 1, MPI_DOUBLE, all.data(), 1, MPI_DOUBLE, MPI_COMM_WORLD);
  return all;
}

}  // namespace tb
