// The PBD constraints packed into batches of independent constraints (no two in a
// batch share a vertex) for the Gauss-Seidel sweep, kind by kind in the order of
// their table (constraint_kinds.h), and the sweeps over them. A batch is projected
// at a time by its kind's vector kernel (batch_kernels.h) on the instruction set
// chosen at run time. Because the constraints of a batch are independent,
// projecting them together gives bitwise the result of projecting them one after
// another in the batches' order (tests/models/numerics/pbd/constraint_batches_test.cc),
// whatever the instruction set and the number of lanes per batch. Batches never
// straddle two colours, and no two constraints of one colour share a vertex, so a
// colour's batches can be split between threads (batch_schedule.h) without
// changing a bit of the result.
//
// The layers: batch_packing.h (which constraint goes into which batch),
// batch_gather.h and batch_kernels.h (SIMD gather, kernels, scatter per kind and
// instruction set), batch_schedule.h (threads, domains, barriers),
// instruction_set.h (what this CPU runs).
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "aligned_rows.h"
#include "batch_packing.h"
#include "constraint_kind.h"
#include "instruction_set.h"
#include "thread_team.h"

namespace tb::pbd {

class ConstraintBatches {
 public:
  static constexpr int kPositionStride = pbd::kPositionStride;

  /// Each kind of `constraints` packed (pack_kind, batch_packing.h) in batches of
  /// `width` lanes (batch_width) for sweeps in `precision`. With `vertex_domain`
  /// (domain_partition.h), each kind's order is domain 0's constraints coloured,
  /// then domain 1's, ..., then the interface's: a thread sweeps a whole domain
  /// with no barrier (project()).
  ///   inverse_mass   #V
  ///   vertex_domain  #V domain indices, or empty: one domain, every constraint
  ///                  in the colour-by-colour group
  ConstraintBatches(const ConstraintSet& constraints, const Eigen::VectorXd& inverse_mass, int width = 4,
                    Precision precision = Precision::Double, const std::vector<int>& vertex_domain = {});

  int width() const { return width_; }
  Precision precision() const { return precision_; }

  /// The batches of each kind, in the order of the constraint set's kinds.
  const std::vector<KindBatches>& kinds() const { return kinds_; }
  /// Those of the kind named `name` (std::invalid_argument if none).
  const KindBatches& of(const std::string& name) const;

  /// One Gauss-Seidel sweep over every kind in turn (a kind with stiffness <= 0
  /// skipped), each forward or in reverse order. The instruction set must have this
  /// packing's width and precision (else std::invalid_argument), and S (double or
  /// float) the packing's precision.
  ///   positions  #V by kPositionStride, row-major (x, y, z, unused), updated in
  ///              place; the unused column is overwritten with zeros
  ///   stiffness  one per kind, in [0, 1]
  ///   records    null, or one per kind: the corrections to sum (batch_layout.h,
  ///              made for this packing by record_corrections)
  template <class S>
  void sweep(S* positions, bool reverse, const std::vector<double>& stiffness, const ProjectionOptions& options,
             InstructionSet isa, std::vector<CorrectionRecord>* records = nullptr) const;

  /// `iterations` sweeps, alternately forward and reverse (symmetric Gauss-Seidel),
  /// the domains shared out between the members of `team` (null: this thread
  /// alone), a barrier, then each interface colour's batches split between them.
  /// The result is bitwise the same for any team size. No heap allocation.
  template <class S>
  void project(S* positions, int iterations, const std::vector<double>& stiffness, const ProjectionOptions& options,
               InstructionSet isa, ThreadTeam* team, std::vector<CorrectionRecord>* records = nullptr) const;

  /// The records (one per kind, in the kinds' order) of the constraints that join a
  /// vertex of a group to a free vertex, for this packing: group_of_vertex[v] >= 0
  /// names v's group (a pinned vertex: inverse mass 0), -1 none; a constraint
  /// touching two groups' vertices is recorded in the group of its first such slot.
  ///   constraints, inverse_mass  those the batches were packed from
  std::vector<CorrectionRecord> record_corrections(const ConstraintSet& constraints,
                                                   const Eigen::VectorXd& inverse_mass,
                                                   const std::vector<int>& group_of_vertex) const;

  /// The kernels' corrections of every constraint at `positions`, nothing moved
  /// (all constraints projected from the same positions): for comparing the SIMD
  /// kernels with the scalar reference (reference_projections.h).
  ///   corrections  one matrix per kind: #C by 3 arity (dp_1, dp_2, ...) per
  ///                constraint row; zero for rows not kept
  template <class S>
  void corrections(const S* positions, const std::vector<double>& stiffness, const ProjectionOptions& options,
                   InstructionSet isa, std::vector<Eigen::MatrixXd>& corrections) const;

 private:
  template <class S>
  void check(InstructionSet isa, const std::vector<double>& stiffness) const;

  int width_;
  Precision precision_;
  std::vector<KindBatches> kinds_;
};

}  // namespace tb::pbd
