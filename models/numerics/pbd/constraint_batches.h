// The PBD constraints packed into batches of independent constraints (no two in a
// batch share a vertex) for the Gauss-Seidel sweep, and the sweep itself, which
// projects a batch at a time with the vector kernels of projection_kernels.h.
// Because the constraints of a batch are independent, projecting them together
// gives bitwise the result of projecting them one after another in the batches'
// order (tests/models/numerics/pbd/constraint_batches_test.cc), whatever the instruction
// set and the number of lanes per batch. Batches never straddle two colours, and
// no two constraints of one colour share a vertex, so a colour's batches can be
// split between threads (thread_team.h) without changing a bit of the result.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <new>
#include <vector>

#include "constraints.h"
#include "lane_math.h"
#include "thread_team.h"

namespace tb::pbd {

struct ConstraintSet;

/// Positions as the sweep wants them: #V rows of (x, y, z, unused) of S, each row
/// one aligned vector (with Eigen's 16-byte alignment every other double row
/// straddles two cache lines: about 5% slower).
template <class S>
class PaddedRows {
 public:
  using Matrix = Eigen::Matrix<S, Eigen::Dynamic, 4, Eigen::RowMajor>;
  explicit PaddedRows(Eigen::Index rows) : rows_(static_cast<size_t>(rows)) {}
  Eigen::Map<Matrix> matrix() { return {rows_.data()->xyz_, static_cast<Eigen::Index>(rows_.size()), 4}; }
  S* data() { return rows_.data()->xyz_; }

 private:
  struct alignas(4 * sizeof(S)) Row {
    S xyz_[4] = {0, 0, 0, 0};
  };
  std::vector<Row> rows_;
};
using PaddedPositions = PaddedRows<double>;
using PaddedPoints = PaddedPositions::Matrix;

/// The vector instructions a sweep runs with, chosen at run time: SSE2 (every
/// x86-64), AVX, AVX-512VL (AVX's 256-bit batches with AVX-512's 32 vector
/// registers: the bending kernel spills less) or AVX-512 (F and DQ, 512-bit
/// batches). In double precision every one gives the same numbers; single
/// precision gives its own (the same on every one).
enum class InstructionSet { Sse2, Avx, Avx512Vl, Avx512 };
/// Every instruction set, whether this CPU has it or not (cpu_supports).
constexpr InstructionSet kInstructionSets[] = {InstructionSet::Sse2, InstructionSet::Avx, InstructionSet::Avx512Vl,
                                               InstructionSet::Avx512};
/// The default: AVX-512VL where the CPU has it, else AVX, else SSE2. AVX-512VL
/// measured 5-8 % faster than AVX in single precision on this project's AMD EPYC
/// (10k vertices, one thread: 2.23-2.37 against 2.42-2.54 ms, best frames of 300);
/// full-width AVX-512 (8 doubles or 16 floats per batch) slower (10k vertices:
/// 5.0 against 4.6 ms double, 3.5 against 2.6 ms single; the gathers' and
/// scatters' shuffles grow with the width), so it runs only when asked.
InstructionSet best_instruction_set();
bool cpu_supports(InstructionSet isa);
const char* name(InstructionSet isa);

/// The number type of a sweep: double, or single for speed (its steady state
/// differs from double's by rounding: README, pbd_solver.h).
enum class Precision { Double, Single };
const char* name(Precision precision);

/// Constraints per batch: one per lane of the instruction set's vectors (SSE2
/// double: two registers of two).
int batch_width(InstructionSet isa, Precision precision);

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

class ConstraintBatches {
 public:
  /// Numbers per vertex in the positions the sweep works on: x, y, z and one
  /// unused, so that a vertex is one vector load.
  static constexpr int kPositionStride = 4;

  /// Keeps the constraints that can move something (one of their vertices has
  /// inverse mass > 0), orders them by a greedy graph colouring and packs
  /// consecutive independent ones into batches of `width` lanes (batch_width) for
  /// sweeps in `precision`. With `vertex_domain` (domain_partition.h), each kind's
  /// order is domain 0's constraints (those with every vertex in domain 0)
  /// coloured, then domain 1's, ..., then the interface's (the rest) coloured: a
  /// thread sweeps a whole domain with no barrier (project()).
  ///   inverse_mass   #V
  ///   vertex_domain  #V domain indices, or empty: one domain, every constraint
  ///                  in the colour-by-colour group
  ConstraintBatches(const ConstraintSet& constraints, const Eigen::VectorXd& inverse_mass, int width = 4,
                    Precision precision = Precision::Double, const std::vector<int>& vertex_domain = {});

  int width() const { return width_; }
  Precision precision() const { return precision_; }

  /// One Gauss-Seidel sweep over all stretch constraints, then all bending
  /// constraints (skipped when k_bend <= 0), forward or in reverse order. The
  /// instruction set must have this packing's width and precision (else
  /// std::invalid_argument), and double or float positions as the precision says.
  ///   positions  #V by kPositionStride, row-major (x, y, z, unused), updated in
  ///              place; the unused column is overwritten with zeros
  void sweep(double* positions, bool reverse, double k_stretch, double k_bend, BendingAngle kind,
             InstructionSet isa) const;
  void sweep(float* positions, bool reverse, double k_stretch, double k_bend, BendingAngle kind,
             InstructionSet isa) const;

  /// `iterations` sweeps, alternately forward and reverse (symmetric Gauss-Seidel),
  /// the domains shared out between the members of `team` (null: this thread
  /// alone), a barrier, then each interface colour's batches split between them.
  /// The result is bitwise the same for any team size.
  void project(double* positions, int iterations, double k_stretch, double k_bend, BendingAngle kind,
               InstructionSet isa, ThreadTeam* team) const;
  void project(float* positions, int iterations, double k_stretch, double k_bend, BendingAngle kind, InstructionSet isa,
               ThreadTeam* team) const;

  /// The kernels' corrections of every constraint at `positions`, nothing moved
  /// (all constraints projected from the same positions): for comparing the SIMD
  /// kernels with the scalar reference (reference_projections.h).
  ///   stretch_corr  #S by 6 (dp1, dp2) per ConstraintSet stretch row, bending_corr
  ///                 #B by 12 (dp1..dp4) per bending row; zero for rows not kept
  void corrections(const double* positions, double k_stretch, double k_bend, BendingAngle kind, InstructionSet isa,
                   Eigen::MatrixXd& stretch_corr, Eigen::MatrixXd& bending_corr) const;
  void corrections(const float* positions, double k_stretch, double k_bend, BendingAngle kind, InstructionSet isa,
                   Eigen::MatrixXd& stretch_corr, Eigen::MatrixXd& bending_corr) const;

  /// The order of projection (forward sweep): indices of rows of the
  /// ConstraintSet's stretch and bending constraints.
  const std::vector<int>& stretch_order() const { return stretch_order_; }
  const std::vector<int>& bending_order() const { return bending_order_; }

  /// Where each colour's batches start (begin.back() = batch count). A vertex of
  /// valence beyond the colouring's 64 colours sends constraints to a last colour
  /// (of its group) whose members may share vertices: in the interface group then
  /// `last_shares_vertices`, and one thread sweeps it.
  struct Colours {
    std::vector<size_t> begin;
    bool last_shares_vertices = false;
  };
  /// The batches of one kind of constraint: lanes in use per batch and the vertex
  /// of each slot and lane; lanes at and beyond a batch's count are padding
  /// (inverse masses 0, vertices of lane 0), computed but not written back.
  struct Layout {
    Colours colours;
    /// Where each group of colours starts (indices into colours.begin): groups
    /// 0 .. domains - 1 are the domains, the last the interface (everything when
    /// there is no partition); group_begin.back() = colour count.
    std::vector<size_t> group_begin;
    size_t domain_count() const { return group_begin.size() - 2; }
    std::vector<int> count;  ///< #batches
    std::vector<int> q;      ///< #batches by slots by width vertex indices
    size_t batch_count() const { return count.size(); }
  };
  const Layout& stretch_layout() const { return stretch_; }
  const Layout& bending_layout() const { return bending_; }
  size_t stretch_batch_count() const { return stretch_.batch_count(); }
  size_t bending_batch_count() const { return bending_.batch_count(); }

  /// The numbers of the batches of one kind in one precision: per batch, each
  /// slot's inverse masses (stretch: their shares w_i / (w_1 + w_2), which are all
  /// the projection needs) and the rest lengths or signed rest angles, lane by lane.
  template <class S>
  struct Numbers {
    std::vector<S, AlignedAllocator<S>> w;     ///< #batches by slots by width
    std::vector<S, AlignedAllocator<S>> rest;  ///< #batches by width
  };

 private:
  template <class S>
  void check(InstructionSet isa) const;

  int width_;
  Precision precision_;
  std::vector<int> stretch_order_, bending_order_;
  Layout stretch_, bending_;
  Numbers<double> stretch_double_, bending_double_;  // filled in double precision
  Numbers<float> stretch_single_, bending_single_;   // filled in single precision
  Eigen::Index stretch_rows_, bending_rows_;         // of the ConstraintSet
};

}  // namespace tb::pbd
