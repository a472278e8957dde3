// Moving a batch's vertices in and out of vector registers for the batched PBD
// sweep: each vertex slot of a batch (one constraint per lane) gathered from the
// padded position rows (aligned_rows.h) with one vector load per vertex and a
// blockwise 4 x 4 transpose, and scattered back the same way. The lane types of
// each instruction set and precision are named here (Lanes); the kernels run on
// them (batch_kernels.h).
#pragma once

#include <cstddef>
#include <type_traits>
#include <utility>

#include "aligned_rows.h"
#include "instruction_set.h"
#include "lane_math.h"

namespace tb::pbd::batches {

using lanes::Triple;

// SSE2 in double precision runs a batch of four as two two-lane registers.
using SseLanes = lanes::Twin<lanes::Vector2>;

/// The lanes of a batch on instruction set `isa` in precision S.
template <InstructionSet isa, class S>
struct LanesOf {  // AVX and AVX-512VL: 256 bits
  using type = lanes::Vector<S, static_cast<int>(32 / sizeof(S))>;
};
template <class S>
struct LanesOf<InstructionSet::Sse2, S> {
  using type = std::conditional_t<std::is_same_v<S, double>, SseLanes, lanes::Vector<float, 4>>;
};
template <class S>
struct LanesOf<InstructionSet::Avx512, S> {
  using type = lanes::Vector<S, static_cast<int>(64 / sizeof(S))>;
};
template <InstructionSet isa, class S>
using Lanes = typename LanesOf<isa, S>::type;

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
  auto row = [&](int lane) { return x + kPositionStride * ptrdiff_t{q[lane]}; };
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
  for (int l = 0; l < W; ++l) rows[l] = load_row<L>(x + kPositionStride * ptrdiff_t{q[l]});
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

}  // namespace tb::pbd::batches
