// The PBD constraints packed into batches of independent constraints (no two in a
// batch share a vertex) for the Gauss-Seidel sweep, and the sweep itself, which
// projects a batch at a time with the vector kernels of projection_kernels.h.
// Because the constraints of a batch are independent, projecting them together
// gives bitwise the result of projecting them one after another in the batches'
// order (tests/models/pbd/constraint_batches_test.cc), on either instruction set.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "constraints.h"
#include "lane_math.h"

namespace tb::pbd {

struct ConstraintSet;

/// Positions as the sweep wants them: #V rows of (x, y, z, unused), each row one
/// 32-byte aligned vector (with Eigen's 16-byte alignment every other row straddles
/// two cache lines: about 5% slower).
using PaddedPoints = Eigen::Matrix<double, Eigen::Dynamic, 4, Eigen::RowMajor>;
class PaddedPositions {
 public:
  explicit PaddedPositions(Eigen::Index rows) : rows_(static_cast<size_t>(rows)) {}
  Eigen::Map<PaddedPoints> matrix() { return {rows_.data()->xyz_, static_cast<Eigen::Index>(rows_.size()), 4}; }
  double* data() { return rows_.data()->xyz_; }

 private:
  struct alignas(4 * sizeof(double)) Row {
    double xyz_[4] = {0, 0, 0, 0};
  };
  std::vector<Row> rows_;
};

/// The vector instructions a sweep runs with: SSE2 (every x86-64, two lanes per
/// instruction) or AVX (four), chosen at run time; the results are the same.
enum class InstructionSet { Sse2, Avx };
InstructionSet best_instruction_set();
const char* name(InstructionSet isa);

class ConstraintBatches {
 public:
  static constexpr int kWidth = lanes::kBatchWidth;
  /// Doubles per vertex in the positions the sweep works on: x, y, z and one
  /// unused, so that a vertex is one vector load.
  static constexpr int kPositionStride = 4;

  /// Keeps the constraints that can move something (one of their vertices has
  /// inverse mass > 0), orders them by a greedy graph colouring and packs
  /// consecutive independent ones into batches.
  ///   inverse_mass  #V
  ConstraintBatches(const ConstraintSet& constraints, const Eigen::VectorXd& inverse_mass);

  /// One Gauss-Seidel sweep over all stretch constraints, then all bending
  /// constraints (skipped when k_bend <= 0), forward or in reverse order.
  ///   positions  #V by kPositionStride, row-major (x, y, z, unused), updated in
  ///              place; the unused column is overwritten with zeros
  void sweep(double* positions, bool reverse, double k_stretch, double k_bend, BendingAngle kind,
             InstructionSet isa) const;

  /// The order of projection (forward sweep): indices of rows of the
  /// ConstraintSet's stretch and bending constraints.
  const std::vector<int>& stretch_order() const { return stretch_order_; }
  const std::vector<int>& bending_order() const { return bending_order_; }
  size_t stretch_batch_count() const { return stretch_.size(); }
  size_t bending_batch_count() const { return bending_.size(); }

  /// N constraint vertices per lane; lanes at and beyond `count` are padding
  /// (inverse masses 0, vertices of lane 0), computed but not written back.
  template <int N>
  struct alignas(lanes::kBatchAlignment) Batch {
    /// Inverse masses of each vertex slot; for stretch (N = 2) their shares
    /// w_i / (w_1 + w_2) (kernels::stretch_shares), which are all the projection needs.
    alignas(lanes::kBatchAlignment) lanes::Batch w[N];
    alignas(lanes::kBatchAlignment) lanes::Batch rest;  ///< rest length or signed rest angle
    int q[N][kWidth];                                   ///< vertex indices
    int count;
  };

 private:
  std::vector<Batch<2>> stretch_;
  std::vector<Batch<4>> bending_;
  std::vector<int> stretch_order_, bending_order_;
};

}  // namespace tb::pbd
