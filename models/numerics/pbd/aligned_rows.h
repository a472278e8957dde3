// Aligned storage for the batched PBD sweep: positions as padded rows (one vector
// load per vertex) and vectors of lanes aligned for their batches.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <new>
#include <vector>

namespace tb::pbd {

/// Numbers per vertex in the positions a sweep works on: x, y, z and one unused,
/// so that a vertex is one vector load.
constexpr int kPositionStride = 4;

/// Positions as the sweep wants them: #V rows of (x, y, z, unused) of S, each row
/// one aligned vector (with Eigen's 16-byte alignment every other double row
/// straddles two cache lines: about 5% slower).
template <class S>
class PaddedRows {
 public:
  using Matrix = Eigen::Matrix<S, Eigen::Dynamic, kPositionStride, Eigen::RowMajor>;
  explicit PaddedRows(Eigen::Index rows) : rows_(static_cast<size_t>(rows)) {}
  Eigen::Map<Matrix> matrix() { return {rows_.data()->xyz_, static_cast<Eigen::Index>(rows_.size()), kPositionStride}; }
  S* data() { return rows_.data()->xyz_; }

 private:
  struct alignas(kPositionStride * sizeof(S)) Row {
    S xyz_[kPositionStride] = {0, 0, 0, 0};
  };
  std::vector<Row> rows_;
};
using PaddedPositions = PaddedRows<double>;
using PaddedPoints = PaddedPositions::Matrix;

/// Vectors with alignment `Align` (for the batches' lanes).
template <class T, size_t Align = 64>
struct AlignedAllocator {
  using value_type = T;
  AlignedAllocator() = default;
  template <class U>
  AlignedAllocator(const AlignedAllocator<U, Align>&) {}
  template <class U>
  struct rebind {
    using other = AlignedAllocator<U, Align>;
  };
  T* allocate(size_t n) { return static_cast<T*>(::operator new(n * sizeof(T), std::align_val_t(Align))); }
  void deallocate(T* p, size_t) { ::operator delete(p, std::align_val_t(Align)); }
  bool operator==(const AlignedAllocator&) const { return true; }
  bool operator!=(const AlignedAllocator&) const { return false; }
};

}  // namespace tb::pbd
