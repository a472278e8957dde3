#include "mpi_session.h"

#include <deal.II/base/mpi.h>
#include <mpi.h>

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

std::vector<double> MpiSession::all_gather(double mine) {
  std::vector<double> all(static_cast<size_t>(size()));
  MPI_Allgather(&mine, 1, MPI_DOUBLE, all.data(), 1, MPI_DOUBLE, MPI_COMM_WORLD);
  return all;
}

std::vector<std::string> MpiSession::gather_to_root(const std::string& mine) {
  const int ranks = size();
  const bool root = rank() == 0;
  int length = static_cast<int>(mine.size());
  std::vector<int> lengths(root ? static_cast<size_t>(ranks) : 0), offsets(lengths.size());
  MPI_Gather(&length, 1, MPI_INT, lengths.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
  std::string joined;
  if (root) {
    for (int r = 1; r < ranks; ++r) offsets[r] = offsets[r - 1] + lengths[r - 1];
    joined.resize(static_cast<size_t>(offsets.back() + lengths.back()));
  }
  MPI_Gatherv(mine.data(), length, MPI_CHAR, joined.data(), lengths.data(), offsets.data(), MPI_CHAR, 0,
              MPI_COMM_WORLD);
  std::vector<std::string> out;
  for (size_t r = 0; r < lengths.size(); ++r) out.push_back(joined.substr(offsets[r], lengths[r]));
  return out;
}

}  // namespace tb
