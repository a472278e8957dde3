#include "constraint_batches.h"

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <stdexcept>

#include "pbd_solver.h"
#include "projection_kernels.h"

namespace tb::pbd {
namespace {

constexpr int kWidth = ConstraintBatches::kWidth;
using lanes::Triple;
using Lanes = lanes::Batch;
template <int N>
using Batch = ConstraintBatches::Batch<N>;
template <int N>
using VertexRows = Eigen::Matrix<int, Eigen::Dynamic, N, Eigen::RowMajor>;

/// The constraints (rows of `vertices`) that can move something: one of their
/// vertices has inverse mass > 0.
template <int N>
std::vector<int> movable(const VertexRows<N>& vertices, const Eigen::VectorXd& w) {
  std::vector<int> kept;
  for (Eigen::Index i = 0; i < vertices.rows(); ++i) {
    bool moves = false;
    for (int j = 0; j < N; ++j) {
      if (vertices(i, j) < 0 || vertices(i, j) >= w.size())
        throw std::invalid_argument("PBD constraints: vertex index out of range of the inverse masses");
      moves = moves || w(vertices(i, j)) > 0;
    }
    if (moves) kept.push_back(static_cast<int>(i));
  }
  return kept;
}

/// The colour of overflowing constraints, whose members may share vertices.
constexpr int kOverflowColour = 64;

/// `kept` reordered by a greedy graph colouring (no two constraints of one colour
/// share a vertex), keeping the original order within a colour, so that runs of
/// consecutive constraints are independent and fill batches. `colour` gets the
/// colour of each entry of the result (ascending).
template <int N>
std::vector<int> colour_order(const VertexRows<N>& vertices, const std::vector<int>& kept, size_t vertex_count,
                              std::vector<int>& colour_of_ordered) {
  std::vector<uint64_t> used(vertex_count, 0);  // colours already taken at each vertex
  std::vector<int> colour(kept.size());
  for (size_t i = 0; i < kept.size(); ++i) {
    uint64_t taken = 0;
    for (int j = 0; j < N; ++j) taken |= used[static_cast<size_t>(vertices(kept[i], j))];
    // The lowest free colour; a vertex with 64 colours around it (valence > 64 for
    // stretch) sends the rest to colour 64, whose constraints may share vertices:
    // the packing below then splits them into smaller batches.
    const int c = ~taken ? __builtin_ctzll(~taken) : kOverflowColour;
    colour[i] = c;
    if (c < kOverflowColour)
      for (int j = 0; j < N; ++j) used[static_cast<size_t>(vertices(kept[i], j))] |= uint64_t{1} << c;
  }
  std::vector<size_t> by_colour(kept.size());
  std::iota(by_colour.begin(), by_colour.end(), size_t{0});
  std::stable_sort(by_colour.begin(), by_colour.end(), [&](size_t a, size_t b) { return colour[a] < colour[b]; });
  std::vector<int> order;
  order.reserve(kept.size());
  colour_of_ordered.clear();
  for (size_t i : by_colour) {
    order.push_back(kept[i]);
    colour_of_ordered.push_back(colour[i]);
  }
  return order;
}

/// Consecutive constraints of `order` packed into batches; a batch closes when it
/// is full, when the next constraint shares a vertex with it or is of another
/// colour. Padding lanes repeat lane 0's first vertex in every slot with inverse
/// mass 0: degenerate, so their corrections are zero.
template <int N>
std::vector<Batch<N>> pack(const VertexRows<N>& vertices, const Eigen::VectorXd& rest, const std::vector<int>& order,
                           const std::vector<int>& colour, const Eigen::VectorXd& w,
                           ConstraintBatches::Colours& colours) {
  std::vector<size_t> last_batch(static_cast<size_t>(w.size()), SIZE_MAX);  // the last batch using each vertex
  std::vector<Batch<N>> batches;
  colours = {};
  for (size_t k = 0; k < order.size(); ++k) {
    const int i = order[k];
    const bool new_colour = k == 0 || colour[k] != colour[k - 1];
    bool fits = !new_colour && batches.back().count < kWidth;
    for (int j = 0; j < N && fits; ++j) fits = last_batch[static_cast<size_t>(vertices(i, j))] != batches.size() - 1;
    if (new_colour) colours.begin.push_back(batches.size());
    if (!fits) batches.push_back(Batch<N>{});
    Batch<N>& b = batches.back();
    const int l = b.count++;
    for (int j = 0; j < N; ++j) {
      const int v = vertices(i, j);
      b.q[j][l] = v;
      b.w[j][l] = w(v);
      last_batch[static_cast<size_t>(v)] = batches.size() - 1;
    }
    b.rest[l] = rest(i);
    if constexpr (N == 2) {  // a stretch batch keeps its correction shares (constant) instead
      double share1, share2;
      kernels::stretch_shares(b.w[0][l], b.w[1][l], share1, share2);
      b.w[0][l] = share1;
      b.w[1][l] = share2;
    }
  }
  colours.begin.push_back(batches.size());
  colours.last_shares_vertices = !colour.empty() && colour.back() == kOverflowColour;
  for (Batch<N>& b : batches)
    for (int l = b.count; l < kWidth; ++l)
      for (int j = 0; j < N; ++j) b.q[j][l] = b.q[0][0];  // w and rest stay 0
  return batches;
}

static_assert(kWidth == ConstraintBatches::kPositionStride, "the gather transposes a square of lanes x coordinates");

// The sweep works on batches of four lanes held as one AVX vector (Lanes) or
// as two SSE2 vectors (Twin<Vector2>); the helpers below come in both kinds.
using SseLanes = lanes::Twin<lanes::Vector2>;

/// A vector at any 8-byte aligned address: one unaligned load or store.
typedef double UnalignedLanes __attribute__((vector_size(sizeof(Lanes)), aligned(alignof(double))));
typedef double UnalignedPair __attribute__((vector_size(sizeof(lanes::Vector2)), aligned(alignof(double))));

TB_PBD_INLINE void load(const double* x, Lanes& r) { r = *reinterpret_cast<const UnalignedLanes*>(x); }
TB_PBD_INLINE void load(const double* x, SseLanes& r) {
  r = {*reinterpret_cast<const UnalignedPair*>(x), *reinterpret_cast<const UnalignedPair*>(x + 2)};
}
TB_PBD_INLINE void store(const Lanes& r, double* x) { *reinterpret_cast<UnalignedLanes*>(x) = r; }
TB_PBD_INLINE void store(const SseLanes& r, double* x) {
  *reinterpret_cast<UnalignedPair*>(x) = r.lo;
  *reinterpret_cast<UnalignedPair*>(x + 2) = r.hi;
}

/// The 4 x 4 transpose of rows (r0, r1, r2, r3), in place.
TB_PBD_INLINE void transpose(Lanes r[4]) {
  using Index = decltype(Lanes{} < Lanes{});
  const Lanes t0 = __builtin_shuffle(r[0], r[1], Index{0, 4, 2, 6}),
              t1 = __builtin_shuffle(r[0], r[1], Index{1, 5, 3, 7});
  const Lanes t2 = __builtin_shuffle(r[2], r[3], Index{0, 4, 2, 6}),
              t3 = __builtin_shuffle(r[2], r[3], Index{1, 5, 3, 7});
  r[0] = __builtin_shuffle(t0, t2, Index{0, 1, 4, 5});
  r[1] = __builtin_shuffle(t1, t3, Index{0, 1, 4, 5});
  r[2] = __builtin_shuffle(t0, t2, Index{2, 3, 6, 7});
  r[3] = __builtin_shuffle(t1, t3, Index{2, 3, 6, 7});
}
TB_PBD_INLINE void transpose(SseLanes r[4]) {
  using Index = decltype(lanes::Vector2{} < lanes::Vector2{});
  const Index even{0, 2}, odd{1, 3};
  const SseLanes t0 = {__builtin_shuffle(r[0].lo, r[1].lo, even), __builtin_shuffle(r[2].lo, r[3].lo, even)};
  const SseLanes t1 = {__builtin_shuffle(r[0].lo, r[1].lo, odd), __builtin_shuffle(r[2].lo, r[3].lo, odd)};
  const SseLanes t2 = {__builtin_shuffle(r[0].hi, r[1].hi, even), __builtin_shuffle(r[2].hi, r[3].hi, even)};
  const SseLanes t3 = {__builtin_shuffle(r[0].hi, r[1].hi, odd), __builtin_shuffle(r[2].hi, r[3].hi, odd)};
  r[0] = t0;
  r[1] = t1;
  r[2] = t2;
  r[3] = t3;
}

/// A stored batch (inverse masses, rest values) as the sweep's lanes.
template <class L>
TB_PBD_INLINE L as_lanes(const lanes::Batch& b) {
  L r;
  __builtin_memcpy(&r, &b, sizeof r);
  return r;
}

/// The positions of each vertex slot of the batch, one lane per constraint: one
/// load per vertex (x, y, z, unused) and a transpose.
template <class L, int N>
TB_PBD_INLINE void gather(const double* x, const Batch<N>& b, Triple<L> p[N]) {
  for (int j = 0; j < N; ++j) {
    L r[4];
    for (int l = 0; l < kWidth; ++l) load(x + ConstraintBatches::kPositionStride * ptrdiff_t{b.q[j][l]}, r[l]);
    transpose(r);
    p[j] = {r[0], r[1], r[2]};
  }
}

/// x = p + corr for the batch's real lanes (the unused fourth coordinate gets 0).
template <class L, int N>
TB_PBD_INLINE void scatter_corrected(double* x, const Batch<N>& b, const Triple<L> p[N], const Triple<L> corr[N]) {
  for (int j = 0; j < N; ++j) {
    const Triple<L> moved = p[j] + corr[j];
    L r[4] = {moved.x, moved.y, moved.z, L{}};
    transpose(r);
    for (int l = 0; l < b.count; ++l) store(r[l], x + ConstraintBatches::kPositionStride * ptrdiff_t{b.q[j][l]});
  }
}

/// Projects one batch: x += the kernels' corrections (Apply), or records them
/// in corr (nothing moved).
template <class L>
TB_PBD_INLINE void project_batch(double* x, const Batch<2>& b, double k, BendingAngle, Triple<L> p[2],
                                 Triple<L> corr[2]) {
  gather(x, b, p);
  kernels::project_stretch(p[0], as_lanes<L>(b.w[0]), p[1], as_lanes<L>(b.w[1]), as_lanes<L>(b.rest), k, corr[0],
                           corr[1]);
}
template <class L>
TB_PBD_INLINE void project_batch(double* x, const Batch<4>& b, double k, BendingAngle kind, Triple<L> p[4],
                                 Triple<L> corr[4]) {
  gather(x, b, p);
  const L w[4] = {as_lanes<L>(b.w[0]), as_lanes<L>(b.w[1]), as_lanes<L>(b.w[2]), as_lanes<L>(b.w[3])};
  kernels::project_bending(p, w, as_lanes<L>(b.rest), k, kind, corr);
}

/// What a sweep needs; `team` may be null (one member).
struct SweepArgs {
  const std::vector<Batch<2>>& stretch;
  const std::vector<Batch<4>>& bending;
  const ConstraintBatches::Colours& stretch_colours;
  const ConstraintBatches::Colours& bending_colours;
  double* x;
  int iterations;
  bool first_reverse;
  double k_stretch, k_bend;
  BendingAngle kind;
  ThreadTeam* team;
};

/// One member's part of a sweep over one kind of constraint: of each colour (in
/// order, or reversed), its share of the batches, then a barrier. A colour whose
/// constraints may share vertices is swept by member 0 alone.
template <class L, int N>
TB_PBD_INLINE void sweep_colours(const SweepArgs& a, const std::vector<Batch<N>>& batches,
                                 const ConstraintBatches::Colours& colours, double k, bool reverse, int member,
                                 int members) {
  const size_t colour_count = colours.begin.size() - 1;
  for (size_t c = 0; c < colour_count; ++c) {
    const size_t colour = reverse ? colour_count - 1 - c : c;
    const size_t begin = colours.begin[colour], count = colours.begin[colour + 1] - begin;
    const bool alone = colours.last_shares_vertices && colour == colour_count - 1;
    const size_t from = alone ? (member == 0 ? 0 : count) : count * static_cast<size_t>(member) / members,
                 to = alone ? (member == 0 ? count : count) : count * static_cast<size_t>(member + 1) / members;
    for (size_t i = from; i < to; ++i) {
      const Batch<N>& b = batches[begin + (reverse ? to - 1 - (i - from) : i)];
      Triple<L> p[N], corr[N];
      project_batch(a.x, b, k, a.kind, p, corr);
      scatter_corrected(a.x, b, p, corr);
    }
    if (members > 1) a.team->barrier();
  }
}

/// Member `member`'s part of every sweep, compiled once per instruction set by the
/// functions below.
template <class L>
TB_PBD_INLINE void sweep_batches(const SweepArgs& a, int member) {
  const int members = a.team ? a.team->size() : 1;
  for (int it = 0; it < a.iterations; ++it) {
    const bool reverse = a.first_reverse != (it % 2 == 1);
    sweep_colours<L>(a, a.stretch, a.stretch_colours, a.k_stretch, reverse, member, members);
    if (a.k_bend > 0) sweep_colours<L>(a, a.bending, a.bending_colours, a.k_bend, reverse, member, members);
  }
}

void sweep_sse2(const SweepArgs& a, int member) { sweep_batches<SseLanes>(a, member); }
__attribute__((target("avx"))) void sweep_avx(const SweepArgs& a, int member) { sweep_batches<Lanes>(a, member); }

/// The corrections of every lane of every batch, stored by constraint row.
template <class L, int N>
TB_PBD_INLINE void record_corrections(const double* x, const std::vector<Batch<N>>& batches,
                                      const std::vector<int>& order, double k, BendingAngle kind,
                                      Eigen::MatrixXd& out) {
  size_t next = 0;  // position in `order` of the batch's lane 0
  for (const Batch<N>& b : batches) {
    Triple<L> p[N], corr[N];
    project_batch(const_cast<double*>(x), b, k, kind, p, corr);  // gather only reads
    for (int j = 0; j < N; ++j) {
      double xyz[3][kWidth];
      store(corr[j].x, xyz[0]);
      store(corr[j].y, xyz[1]);
      store(corr[j].z, xyz[2]);
      for (int l = 0; l < b.count; ++l)
        for (int d = 0; d < 3; ++d) out(order[next + static_cast<size_t>(l)], 3 * j + d) = xyz[d][l];
    }
    next += static_cast<size_t>(b.count);
  }
}

struct CorrectionArgs {
  const ConstraintBatches& batches;
  const std::vector<Batch<2>>& stretch;
  const std::vector<Batch<4>>& bending;
  const double* x;
  double k_stretch, k_bend;
  BendingAngle kind;
  Eigen::MatrixXd &stretch_corr, &bending_corr;
};
template <class L>
TB_PBD_INLINE void corrections_of(const CorrectionArgs& a) {
  record_corrections<L>(a.x, a.stretch, a.batches.stretch_order(), a.k_stretch, a.kind, a.stretch_corr);
  record_corrections<L>(a.x, a.bending, a.batches.bending_order(), a.k_bend, a.kind, a.bending_corr);
}
void corrections_sse2(const CorrectionArgs& a) { corrections_of<SseLanes>(a); }
__attribute__((target("avx"))) void corrections_avx(const CorrectionArgs& a) { corrections_of<Lanes>(a); }

void check_instruction_set(InstructionSet isa) {
  if (isa == InstructionSet::Avx && best_instruction_set() != InstructionSet::Avx)
    throw std::invalid_argument("PBD sweep: this CPU has no AVX");
}

}  // namespace

InstructionSet best_instruction_set() {
  static const InstructionSet best = __builtin_cpu_supports("avx") ? InstructionSet::Avx : InstructionSet::Sse2;
  return best;
}

const char* name(InstructionSet isa) { return isa == InstructionSet::Avx ? "avx" : "sse2"; }

ConstraintBatches::ConstraintBatches(const ConstraintSet& c, const Eigen::VectorXd& w)
    : stretch_rows_(c.stretch.rows()), bending_rows_(c.bending.rows()) {
  const size_t vertex_count = static_cast<size_t>(w.size());
  std::vector<int> colour;
  stretch_order_ = colour_order(c.stretch, movable(c.stretch, w), vertex_count, colour);
  stretch_ = pack(c.stretch, c.stretch_rest, stretch_order_, colour, w, stretch_colours_);
  bending_order_ = colour_order(c.bending, movable(c.bending, w), vertex_count, colour);
  bending_ = pack(c.bending, c.bending_rest, bending_order_, colour, w, bending_colours_);
}

void ConstraintBatches::sweep(double* positions, bool reverse, double k_stretch, double k_bend, BendingAngle kind,
                              InstructionSet isa) const {
  check_instruction_set(isa);
  const SweepArgs args{stretch_, bending_, stretch_colours_, bending_colours_, positions, 1, reverse, k_stretch,
                       k_bend,   kind,     nullptr};
  if (isa == InstructionSet::Avx)
    sweep_avx(args, 0);
  else
    sweep_sse2(args, 0);
}

void ConstraintBatches::project(double* positions, int iterations, double k_stretch, double k_bend, BendingAngle kind,
                                InstructionSet isa, ThreadTeam* team) const {
  check_instruction_set(isa);
  if (team && team->size() == 1) team = nullptr;
  const SweepArgs args{stretch_,   bending_, stretch_colours_, bending_colours_, positions,
                       iterations, false,    k_stretch,        k_bend,           kind,
                       team};
  auto member_sweeps = [&args, isa](int member) {
    if (isa == InstructionSet::Avx)
      sweep_avx(args, member);
    else
      sweep_sse2(args, member);
  };
  if (team)
    team->run(member_sweeps);
  else
    member_sweeps(0);
}

void ConstraintBatches::corrections(const double* positions, double k_stretch, double k_bend, BendingAngle kind,
                                    InstructionSet isa, Eigen::MatrixXd& stretch_corr,
                                    Eigen::MatrixXd& bending_corr) const {
  check_instruction_set(isa);
  stretch_corr = Eigen::MatrixXd::Zero(stretch_rows_, 6);
  bending_corr = Eigen::MatrixXd::Zero(bending_rows_, 12);
  const CorrectionArgs args{*this, stretch_, bending_, positions, k_stretch, k_bend, kind, stretch_corr, bending_corr};
  if (isa == InstructionSet::Avx)
    corrections_avx(args);
  else
    corrections_sse2(args);
}

}  // namespace tb::pbd
