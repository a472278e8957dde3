// The PBD constraints packed into batches of independent constraints (no two in a
// batch share a vertex) for the Gauss-Seidel sweep, and the sweep itself, which
// projects a batch at a time with the vector kernels of projection_kernels.h.
// Because the constraints of a batch are independent, projecting them together
// gives bitwise the result of projecting them one after another in the batches'
// order (tests/models/pbd/constraint_batches_test.cc), on either instruction set.
// Batches never straddle two colours, and no two constraints of one colour share a
// vertex, so a colour's batches can be split between threads (thread_team.h)
// without changing a bit of the result.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "constraints.h"
#include "lane_math.h"
#include "thread_team.h"

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

  /// `iterations` sweeps, alternately forward and reverse (symmetric Gauss-Seidel),
  /// each colour's batches split between the members of `team` (null: this thread
  /// alone). The result is bitwise the same for any team size.
  void project(double* positions, int iterations, double k_stretch, double k_bend, BendingAngle kind,
               InstructionSet isa, ThreadTeam* team) const;

  /// The kernels' corrections of every constraint at `positions`, nothing moved
  /// (all constraints projected from the same positions): for comparing the SIMD
  /// kernels with the scalar reference (reference_projections.h).
  ///   stretch_corr  #S by 6 (dp1, dp2) per ConstraintSet stretch row, bending_corr
  ///                 #B by 12 (dp1..dp4) per bending row; zero for rows not kept
  void corrections(const double* positions, double k_stretch, double k_bend, BendingAngle kind, InstructionSet isa,
                   Eigen::MatrixXd& stretch_corr, Eigen::MatrixXd& bending_corr) const;

  /// The order of projection (forward sweep): indices of rows of the
  /// ConstraintSet's stretch and bending constraints.
  const std::vector<int>& stretch_order() const { return stretch_order_; }
  const std::vector<int>& bending_order() const { return bending_order_; }
  size_t stretch_batch_count() const { return stretch_.size(); }
  size_t bending_batch_count() const { return bending_.size(); }
  /// Colours: batches [begin[c], begin[c + 1]) hold colour c (Colours below).
  const std::vector<size_t>& stretch_colour_begin() const { return stretch_colours_.begin; }
  const std::vector<size_t>& bending_colour_begin() const { return bending_colours_.begin; }

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

  /// Where each colour's batches start (begin.back() = batch count). A vertex of
  /// valence beyond the colouring's 64 colours sends constraints to a last colour
  /// whose members may share vertices: then `last_shares_vertices`, and one thread
  /// sweeps it.
  struct Colours {
    std::vector<size_t> begin;
    bool last_shares_vertices = false;
  };
  const std::vector<Batch<2>>& stretch_batches() const { return stretch_; }
  const std::vector<Batch<4>>& bending_batches() const { return bending_; }

 private:
  std::vector<Batch<2>> stretch_;
  std::vector<Batch<4>> bending_;
  std::vector<int> stretch_order_, bending_order_;
  Colours stretch_colours_, bending_colours_;
  Eigen::Index stretch_rows_, bending_rows_;  // of the ConstraintSet
};

}  // namespace tb::pbd
