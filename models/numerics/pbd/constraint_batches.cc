#include "constraint_batches.h"

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <stdexcept>
#include <string>

#include "pbd_solver.h"
#include "projection_kernels.h"

namespace tb::pbd {
namespace {

using lanes::Triple;
template <int N>
using VertexRows = Eigen::Matrix<int, Eigen::Dynamic, N, Eigen::RowMajor>;
using Layout = ConstraintBatches::Layout;
template <class S>
using Numbers = ConstraintBatches::Numbers<S>;

// ---- packing (setup) ----

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
/// consecutive constraints are independent and fill batches. `colour_of_ordered`
/// gets the colour of each entry of the result (ascending).
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

/// Colour ids of group g are g * kColoursPerGroup + (its colour), so that no two
/// groups share a colour and pack() closes a batch and a colour at a group's end.
constexpr int kColoursPerGroup = kOverflowColour + 1;

/// `kept` ordered group by group (domain 0, 1, ..., then the interface: the
/// constraints whose vertices lie in several domains), each group coloured by
/// colour_order. With no `vertex_domain`, one group: colour_order itself.
template <int N>
std::vector<int> grouped_colour_order(const VertexRows<N>& vertices, const std::vector<int>& kept, size_t vertex_count,
                                      const std::vector<int>& vertex_domain, int domains,
                                      std::vector<int>& colour_of_ordered) {
  if (vertex_domain.empty()) return colour_order(vertices, kept, vertex_count, colour_of_ordered);
  std::vector<std::vector<int>> groups(static_cast<size_t>(domains) + 1);
  for (int i : kept) {
    const int d = vertex_domain[static_cast<size_t>(vertices(i, 0))];
    bool inside = true;
    for (int j = 1; j < N; ++j) inside = inside && vertex_domain[static_cast<size_t>(vertices(i, j))] == d;
    groups[inside ? static_cast<size_t>(d) : groups.size() - 1].push_back(i);
  }
  std::vector<int> order, colours;
  colour_of_ordered.clear();
  for (size_t g = 0; g < groups.size(); ++g) {
    const std::vector<int> part = colour_order(vertices, groups[g], vertex_count, colours);
    order.insert(order.end(), part.begin(), part.end());
    for (int c : colours) colour_of_ordered.push_back(static_cast<int>(g) * kColoursPerGroup + c);
  }
  return order;
}

/// Consecutive constraints of `order` packed into batches of `width` lanes; a
/// batch closes when it is full, when the next constraint shares a vertex with it
/// or is of another colour. Padding lanes repeat lane 0's first vertex in every
/// slot with inverse mass 0: degenerate, so their corrections are zero.
///   groups  domains + 1 (the colour ids' groups: grouped_colour_order)
template <int N>
Layout pack(const VertexRows<N>& vertices, const std::vector<int>& order, const std::vector<int>& colour,
            size_t vertex_count, int width, int groups) {
  std::vector<size_t> last_batch(vertex_count, SIZE_MAX);  // the last batch using each vertex
  std::vector<int> group_of_colour;
  Layout b;
  const size_t W = static_cast<size_t>(width);
  for (size_t k = 0; k < order.size(); ++k) {
    const int i = order[k];
    const bool new_colour = k == 0 || colour[k] != colour[k - 1];
    bool fits = !new_colour && b.count.back() < width;
    for (int j = 0; j < N && fits; ++j) fits = last_batch[static_cast<size_t>(vertices(i, j))] != b.count.size() - 1;
    if (new_colour) {
      b.colours.begin.push_back(b.count.size());
      group_of_colour.push_back(colour[k] / kColoursPerGroup);
    }
    if (!fits) {
      b.count.push_back(0);
      b.q.resize(b.q.size() + N * W, -1);
    }
    const size_t batch = b.count.size() - 1;
    const size_t l = static_cast<size_t>(b.count.back()++);
    for (int j = 0; j < N; ++j) {
      const int v = vertices(i, j);
      b.q[(batch * N + static_cast<size_t>(j)) * W + l] = v;
      last_batch[static_cast<size_t>(v)] = batch;
    }
  }
  b.colours.begin.push_back(b.count.size());
  for (int g = 0; g <= groups; ++g)
    b.group_begin.push_back(static_cast<size_t>(std::lower_bound(group_of_colour.begin(), group_of_colour.end(), g) -
                                                group_of_colour.begin()));
  // Only the last (interface) group is split between threads colour by colour.
  b.colours.last_shares_vertices =
      !colour.empty() && colour.back() == (groups - 1) * kColoursPerGroup + kOverflowColour;
  for (size_t batch = 0; batch < b.count.size(); ++batch)
    for (size_t l = static_cast<size_t>(b.count[batch]); l < W; ++l)
      for (size_t j = 0; j < N; ++j) b.q[(batch * N + j) * W + l] = b.q[batch * N * W];
  return b;
}

/// The batches' inverse masses (stretch: shares) and rest values in precision S.
template <class S, int N>
Numbers<S> numbers(const Layout& b, const std::vector<int>& order, const Eigen::VectorXd& rest,
                   const Eigen::VectorXd& w, int width) {
  const size_t W = static_cast<size_t>(width);
  Numbers<S> n;
  n.w.assign(b.batch_count() * N * W, S(0));
  n.rest.assign(b.batch_count() * W, S(0));
  size_t next = 0;  // position in `order` of the batch's lane 0
  for (size_t batch = 0; batch < b.batch_count(); ++batch) {
    for (size_t l = 0; l < static_cast<size_t>(b.count[batch]); ++l) {
      S slot_w[N];
      for (size_t j = 0; j < N; ++j) slot_w[j] = static_cast<S>(w(b.q[(batch * N + j) * W + l]));
      if constexpr (N == 2) kernels::stretch_shares(slot_w[0], slot_w[1], slot_w[0], slot_w[1]);
      for (size_t j = 0; j < N; ++j) n.w[(batch * N + j) * W + l] = slot_w[j];
      n.rest[batch * W + l] = static_cast<S>(rest(order[next + l]));
    }
    next += static_cast<size_t>(b.count[batch]);
  }
  return n;
}

// ---- the sweep: lanes, gather and scatter for each kind of vector ----

// SSE2 in double precision runs a batch of four as two two-lane registers.
using SseLanes = lanes::Twin<lanes::Vector2>;

/// A vector at any address aligned for its numbers: one unaligned load or store.
template <class S, int W>
struct UnalignedOf {
  typedef S type __attribute__((vector_size(W * sizeof(S)), aligned(alignof(S))));
};
template <class S, int W>
using Unaligned = typename UnalignedOf<S, W>::type;

template <class L>
struct LaneTraits {  // a plain GCC vector
  using S = lanes::Element<L>;
  static constexpr int W = lanes::width<L>();
  using Row = lanes::Vector<S, 4>;
};
template <>
struct LaneTraits<SseLanes> {
  using S = double;
  static constexpr int W = 4;
  using Row = SseLanes;
};

template <class L>
TB_PBD_INLINE L load_lanes(const typename LaneTraits<L>::S* x) {
  using S = typename LaneTraits<L>::S;
  if constexpr (std::is_same_v<L, SseLanes>)
    return {*reinterpret_cast<const Unaligned<S, 2>*>(x), *reinterpret_cast<const Unaligned<S, 2>*>(x + 2)};
  else
    return *reinterpret_cast<const Unaligned<S, LaneTraits<L>::W>*>(x);
}
template <class L>
TB_PBD_INLINE typename LaneTraits<L>::Row load_row(const typename LaneTraits<L>::S* x) {
  return load_lanes<std::conditional_t<std::is_same_v<L, SseLanes>, SseLanes, typename LaneTraits<L>::Row>>(x);
}
template <class R, class S>
TB_PBD_INLINE void store_row(const R& r, S* x) {
  if constexpr (std::is_same_v<R, SseLanes>) {
    *reinterpret_cast<Unaligned<S, 2>*>(x) = r.lo;
    *reinterpret_cast<Unaligned<S, 2>*>(x + 2) = r.hi;
  } else {
    *reinterpret_cast<Unaligned<S, 4>*>(x) = r;
  }
}

/// Shuffle masks of the blockwise 4 x 4 transpose: for output element i of a
/// vector of W numbers (block b = i / 4, e = i % 4; second operand from W on).
template <int W>
struct Masks {
  // t0 = (a.b0, c.b0, a.b2, c.b2) per block; t1 = (a.b1, c.b1, a.b3, c.b3).
  static constexpr int pair_even(int i) { return 4 * (i / 4) + (i % 4 / 2) * 2 + (i % 2) * W; }
  static constexpr int pair_odd(int i) { return pair_even(i) + 1; }
  // x = (t0.b0, t0.b1, t2.b0, t2.b1); z = (t0.b2, t0.b3, t2.b2, t2.b3).
  static constexpr int low_halves(int i) { return 4 * (i / 4) + (i % 2) + (i % 4 / 2) * W; }
  static constexpr int high_halves(int i) { return low_halves(i) + 2; }
  // concatenation of two vectors, and block k of a vector
  static constexpr int concat(int i) { return i; }
};

template <int W, class V, size_t... I>
TB_PBD_INLINE V shuffle_pair_even(V a, V b, std::index_sequence<I...>) {
  return __builtin_shufflevector(a, b, Masks<W>::pair_even(I)...);
}
template <int W, class V, size_t... I>
TB_PBD_INLINE V shuffle_pair_odd(V a, V b, std::index_sequence<I...>) {
  return __builtin_shufflevector(a, b, Masks<W>::pair_odd(I)...);
}
template <int W, class V, size_t... I>
TB_PBD_INLINE V shuffle_low_halves(V a, V b, std::index_sequence<I...>) {
  return __builtin_shufflevector(a, b, Masks<W>::low_halves(I)...);
}
template <int W, class V, size_t... I>
TB_PBD_INLINE V shuffle_high_halves(V a, V b, std::index_sequence<I...>) {
  return __builtin_shufflevector(a, b, Masks<W>::high_halves(I)...);
}
template <class V, size_t... I>
TB_PBD_INLINE auto concat(V a, V b, std::index_sequence<I...>) {
  return __builtin_shufflevector(a, b, static_cast<int>(I)...);
}
template <int First, class V, size_t... I>
TB_PBD_INLINE auto block(V a, std::index_sequence<I...>) {
  return __builtin_shufflevector(a, a, (First + static_cast<int>(I))...);
}

/// In place, within every block of four numbers of c[0..3], the 4 x 4 transpose
/// (an involution): rows in, coordinates out, and back.
template <class L>
TB_PBD_INLINE void transpose_blocks(L c[4]) {
  if constexpr (std::is_same_v<L, SseLanes>) {
    using Index = decltype(lanes::Vector2{} < lanes::Vector2{});
    const Index even{0, 2}, odd{1, 3};
    const SseLanes t0 = {__builtin_shuffle(c[0].lo, c[1].lo, even), __builtin_shuffle(c[2].lo, c[3].lo, even)};
    const SseLanes t1 = {__builtin_shuffle(c[0].lo, c[1].lo, odd), __builtin_shuffle(c[2].lo, c[3].lo, odd)};
    const SseLanes t2 = {__builtin_shuffle(c[0].hi, c[1].hi, even), __builtin_shuffle(c[2].hi, c[3].hi, even)};
    const SseLanes t3 = {__builtin_shuffle(c[0].hi, c[1].hi, odd), __builtin_shuffle(c[2].hi, c[3].hi, odd)};
    c[0] = t0;
    c[1] = t1;
    c[2] = t2;
    c[3] = t3;
  } else {
    constexpr int W = lanes::width<L>();
    const auto seq = std::make_index_sequence<W>{};
    const L t0 = shuffle_pair_even<W>(c[0], c[1], seq), t1 = shuffle_pair_odd<W>(c[0], c[1], seq);
    const L t2 = shuffle_pair_even<W>(c[2], c[3], seq), t3 = shuffle_pair_odd<W>(c[2], c[3], seq);
    c[0] = shuffle_low_halves<W>(t0, t2, seq);
    c[1] = shuffle_low_halves<W>(t1, t3, seq);
    c[2] = shuffle_high_halves<W>(t0, t2, seq);
    c[3] = shuffle_high_halves<W>(t1, t3, seq);
  }
}

/// The rows of lanes k, k + 4, k + 8, ... side by side in one vector (lane order
/// of the blocks: block m holds row k + 4 m).
template <class L, class R>
TB_PBD_INLINE L interleave(const R* rows, int k) {
  constexpr int W = LaneTraits<L>::W;
  if constexpr (W == 4) {
    return rows[k];
  } else if constexpr (W == 8) {
    return concat(rows[k], rows[k + 4], std::make_index_sequence<8>{});
  } else {
    static_assert(W == 16, "batches of 4, 8 or 16 lanes");
    const auto a = concat(rows[k], rows[k + 4], std::make_index_sequence<8>{});
    const auto b = concat(rows[k + 8], rows[k + 12], std::make_index_sequence<8>{});
    return concat(a, b, std::make_index_sequence<16>{});
  }
}

/// Row k + 4 m of a vector made by interleave, m = 0 .. W/4 - 1, stored.
template <class L, class S>
TB_PBD_INLINE void store_rows(const L& c, int k, S* x, const int* q, int count) {
  constexpr int W = LaneTraits<L>::W;
  auto row = [&](int lane) { return x + ConstraintBatches::kPositionStride * ptrdiff_t{q[lane]}; };
  if constexpr (W == 4) {
    if (k < count) store_row(c, row(k));
  } else {
    const auto four = std::make_index_sequence<4>{};
    if (k < count) store_row(block<0>(c, four), row(k));
    if (k + 4 < count) store_row(block<4>(c, four), row(k + 4));
    if constexpr (W == 16) {
      if (k + 8 < count) store_row(block<8>(c, four), row(k + 8));
      if (k + 12 < count) store_row(block<12>(c, four), row(k + 12));
    }
  }
}

/// The positions of one vertex slot of a batch, one lane per constraint: one load
/// per vertex (x, y, z, unused) and transposes.
template <class L>
TB_PBD_INLINE Triple<L> gather(const typename LaneTraits<L>::S* x, const int* q) {
  constexpr int W = LaneTraits<L>::W;
  typename LaneTraits<L>::Row rows[W];
  for (int l = 0; l < W; ++l) rows[l] = load_row<L>(x + ConstraintBatches::kPositionStride * ptrdiff_t{q[l]});
  L c[4];
  for (int k = 0; k < 4; ++k) c[k] = interleave<L>(rows, k);
  transpose_blocks(c);
  return {c[0], c[1], c[2]};
}

/// x = p + corr for one vertex slot's real lanes (the unused fourth coordinate gets 0).
template <class L>
TB_PBD_INLINE void scatter_corrected(typename LaneTraits<L>::S* x, const int* q, int count, const Triple<L>& p,
                                     const Triple<L>& corr) {
  const Triple<L> moved = p + corr;
  L c[4] = {moved.x, moved.y, moved.z, L{}};
  transpose_blocks(c);
  for (int k = 0; k < 4; ++k) store_rows(c[k], k, x, q, count);
}

/// What a sweep needs; `team` may be null (one member).
template <class S>
struct SweepArgs {
  const Layout& stretch;
  const Layout& bending;
  const Numbers<S>& stretch_numbers;
  const Numbers<S>& bending_numbers;
  S* x;
  int iterations;
  bool first_reverse;
  double k_stretch, k_bend;
  BendingAngle kind;
  ThreadTeam* team;
};

/// Projects batch `b` of one kind: corr gets the corrections of each slot.
template <class L, int N>
TB_PBD_INLINE void project_batch(const typename LaneTraits<L>::S* x, const Layout& layout,
                                 const Numbers<typename LaneTraits<L>::S>& n, size_t b, double k, BendingAngle kind,
                                 Triple<L> p[N], Triple<L> corr[N]) {
  constexpr size_t W = LaneTraits<L>::W;
  for (size_t j = 0; j < N; ++j) p[j] = gather<L>(x, &layout.q[(b * N + j) * W]);
  L w[N];
  for (size_t j = 0; j < N; ++j) w[j] = load_lanes<L>(&n.w[(b * N + j) * W]);
  const L rest = load_lanes<L>(&n.rest[b * W]);
  if constexpr (N == 2)
    kernels::project_stretch(p[0], w[0], p[1], w[1], rest, k, corr[0], corr[1]);
  else
    kernels::project_bending(p, w, rest, k, kind, corr);
}

/// A colour with fewer batches than this per member is swept by member 0 alone:
/// splitting it would cost more in barriers and idle members than it saves (the
/// greedy colouring leaves a tail of small colours: at 10k vertices the last
/// bending colours hold 122, 50, 21, 13, 7, 4 and 1 batches of eight).
constexpr size_t kMinBatchesPerMember = 16;

/// Projects batches [begin, end) in order (or reversed), each written back before the next.
template <class L, int N>
TB_PBD_INLINE void sweep_range(const SweepArgs<typename LaneTraits<L>::S>& a, const Layout& layout,
                               const Numbers<typename LaneTraits<L>::S>& n, double k, size_t begin, size_t end,
                               bool reverse) {
  constexpr size_t W = LaneTraits<L>::W;
  for (size_t i = begin; i < end; ++i) {
    const size_t b = reverse ? end - 1 - (i - begin) : i;
    Triple<L> p[N], corr[N];
    project_batch<L, N>(a.x, layout, n, b, k, a.kind, p, corr);
    for (size_t j = 0; j < N; ++j) scatter_corrected(a.x, &layout.q[(b * N + j) * W], layout.count[b], p[j], corr[j]);
  }
}

/// One member's part of a sweep over the interface group of one kind of
/// constraint (everything, with no domains): of each colour (in order, or
/// reversed), its share of the batches, then a barrier. A colour whose
/// constraints may share vertices, or a small one, is swept by member 0 alone, and
/// consecutive such colours need no barrier between them (one thread, in order).
/// Who sweeps what never changes the result: within a colour the constraints are
/// independent, and colours follow each other in order.
template <class L, int N>
TB_PBD_INLINE void sweep_colours(const SweepArgs<typename LaneTraits<L>::S>& a, const Layout& layout,
                                 const Numbers<typename LaneTraits<L>::S>& n, double k, bool reverse, int member,
                                 int members) {
  const size_t first = layout.group_begin[layout.domain_count()], colour_end = layout.group_begin.back();
  const size_t colour_count = colour_end - first;
  auto size = [&](size_t colour) { return layout.colours.begin[colour + 1] - layout.colours.begin[colour]; };
  auto alone = [&](size_t colour) {
    return members == 1 || (layout.colours.last_shares_vertices && colour == colour_end - 1) ||
           size(colour) < kMinBatchesPerMember * static_cast<size_t>(members);
  };
  for (size_t c = 0; c < colour_count; ++c) {
    const size_t colour = first + (reverse ? colour_count - 1 - c : c);
    const size_t begin = layout.colours.begin[colour], count = size(colour);
    const bool by_one = alone(colour);
    const size_t from = by_one ? (member == 0 ? 0 : count) : count * static_cast<size_t>(member) / members,
                 to = by_one ? count : count * static_cast<size_t>(member + 1) / members;
    sweep_range<L, N>(a, layout, n, k, begin + from, begin + to, reverse);
    // The next colour may start when every member is done with this one, unless
    // member 0 sweeps both (the next kind of constraint or sweep: always a barrier).
    const bool last = c + 1 == colour_count;
    const size_t next = reverse ? colour - 1 : colour + 1;
    if (members > 1 && (last || !by_one || !alone(next))) a.team->barrier();
  }
}

/// One member's part of a sweep over the domains of one kind of constraint:
/// domains member, member + members, ..., each whole (its batches in order, or
/// reversed), then a barrier. Domains share no vertex, so who sweeps which does
/// not change the result.
template <class L, int N>
TB_PBD_INLINE void sweep_domains(const SweepArgs<typename LaneTraits<L>::S>& a, const Layout& layout,
                                 const Numbers<typename LaneTraits<L>::S>& n, double k, bool reverse, int member,
                                 int members) {
  const size_t domains = layout.domain_count();
  for (size_t d = static_cast<size_t>(member); d < domains; d += static_cast<size_t>(members))
    sweep_range<L, N>(a, layout, n, k, layout.colours.begin[layout.group_begin[d]],
                      layout.colours.begin[layout.group_begin[d + 1]], reverse);
  if (members > 1) a.team->barrier();
}

/// One member's part of a sweep over one kind of constraint in the batches'
/// order (domains, then the interface), or reversed.
template <class L, int N>
TB_PBD_INLINE void sweep_kind(const SweepArgs<typename LaneTraits<L>::S>& a, const Layout& layout,
                              const Numbers<typename LaneTraits<L>::S>& n, double k, bool reverse, int member,
                              int members) {
  const bool domains = layout.domain_count() > 0;
  if (domains && !reverse) sweep_domains<L, N>(a, layout, n, k, reverse, member, members);
  sweep_colours<L, N>(a, layout, n, k, reverse, member, members);
  if (domains && reverse) sweep_domains<L, N>(a, layout, n, k, reverse, member, members);
}

/// Member `member`'s part of every sweep, compiled once per instruction set and
/// precision by the functions below.
template <class L>
TB_PBD_INLINE void sweep_batches(const SweepArgs<typename LaneTraits<L>::S>& a, int member) {
  const int members = a.team ? a.team->size() : 1;
  for (int it = 0; it < a.iterations; ++it) {
    const bool reverse = a.first_reverse != (it % 2 == 1);
    sweep_kind<L, 2>(a, a.stretch, a.stretch_numbers, a.k_stretch, reverse, member, members);
    if (a.k_bend > 0) sweep_kind<L, 4>(a, a.bending, a.bending_numbers, a.k_bend, reverse, member, members);
  }
}

/// The corrections of every lane of every batch of one kind, stored by constraint row.
template <class L, int N>
TB_PBD_INLINE void record_corrections(const typename LaneTraits<L>::S* x, const Layout& layout,
                                      const Numbers<typename LaneTraits<L>::S>& n, const std::vector<int>& order,
                                      double k, BendingAngle kind, Eigen::MatrixXd& out) {
  using S = typename LaneTraits<L>::S;
  constexpr int W = LaneTraits<L>::W;
  size_t next = 0;  // position in `order` of the batch's lane 0
  for (size_t b = 0; b < layout.batch_count(); ++b) {
    Triple<L> p[N], corr[N];
    project_batch<L, N>(x, layout, n, b, k, kind, p, corr);
    for (int j = 0; j < N; ++j) {
      S xyz[3][W];
      __builtin_memcpy(xyz[0], &corr[j].x, sizeof(L));
      __builtin_memcpy(xyz[1], &corr[j].y, sizeof(L));
      __builtin_memcpy(xyz[2], &corr[j].z, sizeof(L));
      for (int l = 0; l < layout.count[b]; ++l)
        for (int d = 0; d < 3; ++d) out(order[next + static_cast<size_t>(l)], 3 * j + d) = xyz[d][l];
    }
    next += static_cast<size_t>(layout.count[b]);
  }
}

template <class S>
struct CorrectionArgs {
  const ConstraintBatches& batches;
  const Numbers<S>& stretch_numbers;
  const Numbers<S>& bending_numbers;
  const S* x;
  double k_stretch, k_bend;
  BendingAngle kind;
  Eigen::MatrixXd &stretch_corr, &bending_corr;
};
template <class L>
TB_PBD_INLINE void corrections_of(const CorrectionArgs<typename LaneTraits<L>::S>& a) {
  record_corrections<L, 2>(a.x, a.batches.stretch_layout(), a.stretch_numbers, a.batches.stretch_order(), a.k_stretch,
                           a.kind, a.stretch_corr);
  record_corrections<L, 4>(a.x, a.batches.bending_layout(), a.bending_numbers, a.batches.bending_order(), a.k_bend,
                           a.kind, a.bending_corr);
}

// One function per instruction set and precision, each with its target.
#define TB_AVX512 __attribute__((target("avx512f,avx512dq")))
#define TB_AVX512VL __attribute__((target("avx512f,avx512dq,avx512vl")))
void sweep_sse2(const SweepArgs<double>& a, int m) { sweep_batches<SseLanes>(a, m); }
__attribute__((target("avx"))) void sweep_avx(const SweepArgs<double>& a, int m) {
  sweep_batches<lanes::Vector<double, 4>>(a, m);
}
TB_AVX512VL void sweep_avx512vl(const SweepArgs<double>& a, int m) { sweep_batches<lanes::Vector<double, 4>>(a, m); }
TB_AVX512 void sweep_avx512(const SweepArgs<double>& a, int m) { sweep_batches<lanes::Vector<double, 8>>(a, m); }
void sweep_sse2(const SweepArgs<float>& a, int m) { sweep_batches<lanes::Vector<float, 4>>(a, m); }
__attribute__((target("avx"))) void sweep_avx(const SweepArgs<float>& a, int m) {
  sweep_batches<lanes::Vector<float, 8>>(a, m);
}
TB_AVX512VL void sweep_avx512vl(const SweepArgs<float>& a, int m) { sweep_batches<lanes::Vector<float, 8>>(a, m); }
TB_AVX512 void sweep_avx512(const SweepArgs<float>& a, int m) { sweep_batches<lanes::Vector<float, 16>>(a, m); }

void corrections_sse2(const CorrectionArgs<double>& a) { corrections_of<SseLanes>(a); }
__attribute__((target("avx"))) void corrections_avx(const CorrectionArgs<double>& a) {
  corrections_of<lanes::Vector<double, 4>>(a);
}
TB_AVX512 void corrections_avx512(const CorrectionArgs<double>& a) { corrections_of<lanes::Vector<double, 8>>(a); }
void corrections_sse2(const CorrectionArgs<float>& a) { corrections_of<lanes::Vector<float, 4>>(a); }
__attribute__((target("avx"))) void corrections_avx(const CorrectionArgs<float>& a) {
  corrections_of<lanes::Vector<float, 8>>(a);
}
TB_AVX512 void corrections_avx512(const CorrectionArgs<float>& a) { corrections_of<lanes::Vector<float, 16>>(a); }
TB_AVX512VL void corrections_avx512vl(const CorrectionArgs<double>& a) { corrections_of<lanes::Vector<double, 4>>(a); }
TB_AVX512VL void corrections_avx512vl(const CorrectionArgs<float>& a) { corrections_of<lanes::Vector<float, 8>>(a); }
#undef TB_AVX512
#undef TB_AVX512VL

template <class S>
void run_sweeps(const SweepArgs<S>& args, InstructionSet isa) {
  auto member_sweeps = [&args, isa](int member) {
    switch (isa) {
      case InstructionSet::Avx512:
        sweep_avx512(args, member);
        break;
      case InstructionSet::Avx512Vl:
        sweep_avx512vl(args, member);
        break;
      case InstructionSet::Avx:
        sweep_avx(args, member);
        break;
      default:
        sweep_sse2(args, member);
    }
  };
  if (args.team)
    args.team->run(member_sweeps);
  else
    member_sweeps(0);
}

template <class S>
void run_corrections(const CorrectionArgs<S>& args, InstructionSet isa) {
  switch (isa) {
    case InstructionSet::Avx512:
      corrections_avx512(args);
      break;
    case InstructionSet::Avx512Vl:
      corrections_avx512vl(args);
      break;
    case InstructionSet::Avx:
      corrections_avx(args);
      break;
    default:
      corrections_sse2(args);
  }
}

}  // namespace

bool cpu_supports(InstructionSet isa) {
  switch (isa) {
    case InstructionSet::Avx512:
      return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq");
    case InstructionSet::Avx512Vl:
      return cpu_supports(InstructionSet::Avx512) && __builtin_cpu_supports("avx512vl");
    case InstructionSet::Avx:
      return __builtin_cpu_supports("avx");
    default:
      return true;
  }
}

InstructionSet best_instruction_set() {
  static const InstructionSet best = cpu_supports(InstructionSet::Avx512Vl) ? InstructionSet::Avx512Vl
                                     : cpu_supports(InstructionSet::Avx)    ? InstructionSet::Avx
                                                                            : InstructionSet::Sse2;
  return best;
}

const char* name(InstructionSet isa) {
  switch (isa) {
    case InstructionSet::Avx512:
      return "avx512";
    case InstructionSet::Avx512Vl:
      return "avx512vl";
    case InstructionSet::Avx:
      return "avx";
    default:
      return "sse2";
  }
}

const char* name(Precision precision) { return precision == Precision::Single ? "single" : "double"; }

int batch_width(InstructionSet isa, Precision precision) {
  const int bytes = isa == InstructionSet::Avx512 ? 64 : isa == InstructionSet::Sse2 ? 16 : 32;
  return std::max(4, bytes / (precision == Precision::Single ? 4 : 8));  // SSE2 double: four as two registers
}

ConstraintBatches::ConstraintBatches(const ConstraintSet& c, const Eigen::VectorXd& w, int width, Precision precision,
                                     const std::vector<int>& vertex_domain)
    : width_(width), precision_(precision), stretch_rows_(c.stretch.rows()), bending_rows_(c.bending.rows()) {
  if (width != 4 && width != 8 && width != 16)
    throw std::invalid_argument("PBD constraint batches: 4, 8 or 16 lanes, not " + std::to_string(width));
  const size_t vertex_count = static_cast<size_t>(w.size());
  if (!vertex_domain.empty() && vertex_domain.size() != vertex_count)
    throw std::invalid_argument("PBD constraint batches: one domain per vertex expected");
  const int domains = vertex_domain.empty() ? 0 : *std::max_element(vertex_domain.begin(), vertex_domain.end()) + 1;
  if (!vertex_domain.empty() && *std::min_element(vertex_domain.begin(), vertex_domain.end()) < 0)
    throw std::invalid_argument("PBD constraint batches: negative vertex domain");
  std::vector<int> colour;
  stretch_order_ = grouped_colour_order(c.stretch, movable(c.stretch, w), vertex_count, vertex_domain, domains, colour);
  stretch_ = pack(c.stretch, stretch_order_, colour, vertex_count, width, domains + 1);
  bending_order_ = grouped_colour_order(c.bending, movable(c.bending, w), vertex_count, vertex_domain, domains, colour);
  bending_ = pack(c.bending, bending_order_, colour, vertex_count, width, domains + 1);
  if (precision == Precision::Double) {
    stretch_double_ = numbers<double, 2>(stretch_, stretch_order_, c.stretch_rest, w, width);
    bending_double_ = numbers<double, 4>(bending_, bending_order_, c.bending_rest, w, width);
  } else {
    stretch_single_ = numbers<float, 2>(stretch_, stretch_order_, c.stretch_rest, w, width);
    bending_single_ = numbers<float, 4>(bending_, bending_order_, c.bending_rest, w, width);
  }
}

template <class S>
void ConstraintBatches::check(InstructionSet isa) const {
  const Precision p = std::is_same_v<S, float> ? Precision::Single : Precision::Double;
  if (!cpu_supports(isa)) throw std::invalid_argument(std::string("PBD sweep: this CPU has no ") + name(isa));
  if (p != precision_)
    throw std::invalid_argument(std::string("PBD sweep: ") + name(p) + " positions for batches packed in " +
                                name(precision_) + " precision");
  if (batch_width(isa, precision_) != width_)
    throw std::invalid_argument(std::string("PBD sweep: ") + name(isa) + " sweeps batches of " +
                                std::to_string(batch_width(isa, precision_)) + " lanes, these have " +
                                std::to_string(width_));
}

void ConstraintBatches::sweep(double* positions, bool reverse, double k_stretch, double k_bend, BendingAngle kind,
                              InstructionSet isa) const {
  check<double>(isa);
  run_sweeps(SweepArgs<double>{stretch_, bending_, stretch_double_, bending_double_, positions, 1, reverse, k_stretch,
                               k_bend, kind, nullptr},
             isa);
}

void ConstraintBatches::sweep(float* positions, bool reverse, double k_stretch, double k_bend, BendingAngle kind,
                              InstructionSet isa) const {
  check<float>(isa);
  run_sweeps(SweepArgs<float>{stretch_, bending_, stretch_single_, bending_single_, positions, 1, reverse, k_stretch,
                              k_bend, kind, nullptr},
             isa);
}

void ConstraintBatches::project(double* positions, int iterations, double k_stretch, double k_bend, BendingAngle kind,
                                InstructionSet isa, ThreadTeam* team) const {
  check<double>(isa);
  if (team && team->size() == 1) team = nullptr;
  run_sweeps(SweepArgs<double>{stretch_, bending_, stretch_double_, bending_double_, positions, iterations, false,
                               k_stretch, k_bend, kind, team},
             isa);
}

void ConstraintBatches::project(float* positions, int iterations, double k_stretch, double k_bend, BendingAngle kind,
                                InstructionSet isa, ThreadTeam* team) const {
  check<float>(isa);
  if (team && team->size() == 1) team = nullptr;
  run_sweeps(SweepArgs<float>{stretch_, bending_, stretch_single_, bending_single_, positions, iterations, false,
                              k_stretch, k_bend, kind, team},
             isa);
}

void ConstraintBatches::corrections(const double* positions, double k_stretch, double k_bend, BendingAngle kind,
                                    InstructionSet isa, Eigen::MatrixXd& stretch_corr,
                                    Eigen::MatrixXd& bending_corr) const {
  check<double>(isa);
  stretch_corr = Eigen::MatrixXd::Zero(stretch_rows_, 6);
  bending_corr = Eigen::MatrixXd::Zero(bending_rows_, 12);
  run_corrections(CorrectionArgs<double>{*this, stretch_double_, bending_double_, positions, k_stretch, k_bend, kind,
                                         stretch_corr, bending_corr},
                  isa);
}

void ConstraintBatches::corrections(const float* positions, double k_stretch, double k_bend, BendingAngle kind,
                                    InstructionSet isa, Eigen::MatrixXd& stretch_corr,
                                    Eigen::MatrixXd& bending_corr) const {
  check<float>(isa);
  stretch_corr = Eigen::MatrixXd::Zero(stretch_rows_, 6);
  bending_corr = Eigen::MatrixXd::Zero(bending_rows_, 12);
  run_corrections(CorrectionArgs<float>{*this, stretch_single_, bending_single_, positions, k_stretch, k_bend, kind,
                                        stretch_corr, bending_corr},
                  isa);
}

}  // namespace tb::pbd
