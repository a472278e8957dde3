// A kind's batched projection compiled once per instruction set and precision:
// each batch's vertex slots gathered (batch_gather.h), the kind's kernel run on
// its lanes (projection_kernels.h style over lane_math.h), the corrections
// scattered back; one function per instruction set, each with its target, in the
// table a ConstraintKind holds (BatchKernels), from which a sweep picks the
// instruction set at run time. Included by the file that defines a kind
// (define_constraint_kind.h), which must have the lane-math compile options
// (models/CMakeLists.txt): no FMA contraction, so a lane equals the scalar kernel.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <type_traits>
#include <utility>
#include <vector>

#include "batch_gather.h"
#include "constraint_kind.h"

namespace tb::pbd::batches {

/// Projects batch `b` of kind K: corr gets the corrections of each slot.
template <class K, class L>
TB_PBD_INLINE void project_batch(const typename LaneTraits<L>::S* x, const KindSweep<typename LaneTraits<L>::S>& k,
                                 size_t b, Triple<L> p[K::kArity], Triple<L> corr[K::kArity]) {
  constexpr size_t N = K::kArity, R = K::kRestValues, W = LaneTraits<L>::W;
  for (size_t j = 0; j < N; ++j) p[j] = gather<L>(x, &k.layout.q[(b * N + j) * W]);
  L w[N];
  for (size_t j = 0; j < N; ++j) w[j] = load_lanes<L>(&k.numbers.w[(b * N + j) * W]);
  L rest[R > 0 ? R : 1];
  for (size_t r = 0; r < R; ++r) rest[r] = load_lanes<L>(&k.numbers.rest[(b * R + r) * W]);
  K::project(p, w, rest, k.stiffness, k.options, corr);
}

/// Lane values of a batch's corrections: xyz[j][d][l] is slot j's component d in lane l.
template <class L, size_t N>
TB_PBD_INLINE void spill_corrections(const Triple<L> corr[N], typename LaneTraits<L>::S xyz[N][3][LaneTraits<L>::W]) {
  for (size_t j = 0; j < N; ++j) {
    __builtin_memcpy(xyz[j][0], &corr[j].x, sizeof(L));
    __builtin_memcpy(xyz[j][1], &corr[j].y, sizeof(L));
    __builtin_memcpy(xyz[j][2], &corr[j].z, sizeof(L));
  }
}

/// Batch b's recorded lanes (CorrectionRecord): their momentum added to their sums.
template <class K, class L>
TB_PBD_INLINE void record_batch(CorrectionRecord& record, size_t b, const Triple<L> corr[K::kArity]) {
  using S = typename LaneTraits<L>::S;
  constexpr size_t N = K::kArity, W = LaneTraits<L>::W;
  const int first = record.batch_first[b], last = record.batch_first[b + 1];
  if (first == last) return;
  S xyz[N][3][W];
  spill_corrections<L, N>(corr, xyz);
  for (int r = first; r < last; ++r) {
    const int l = record.lane[static_cast<size_t>(r)];
    record.add(r, [&](int j) {
      return Vec3(double(xyz[j][0][l]), double(xyz[j][1][l]), double(xyz[j][2][l]));
    });
  }
}

/// Projects batches [begin, end) of kind K in order (or reversed), each written
/// back before the next; with kRecord, the recorded lanes' momentum summed too.
template <class K, class L, bool kRecord>
TB_PBD_INLINE void sweep_batches(typename LaneTraits<L>::S* x, const KindSweep<typename LaneTraits<L>::S>& k,
                                 size_t begin, size_t end, bool reverse) {
  constexpr size_t N = K::kArity, W = LaneTraits<L>::W;
  for (size_t i = begin; i < end; ++i) {
    const size_t b = reverse ? end - 1 - (i - begin) : i;
    Triple<L> p[N], corr[N];
    project_batch<K, L>(x, k, b, p, corr);
    if constexpr (kRecord) record_batch<K, L>(*k.record, b, corr);
    for (size_t j = 0; j < N; ++j) scatter_corrected(x, &k.layout.q[(b * N + j) * W], k.layout.count[b], p[j], corr[j]);
  }
}
/// sweep_batches, recording only when the kind has a record (the plain loop otherwise).
template <class K, class L>
TB_PBD_INLINE void sweep_range(typename LaneTraits<L>::S* x, const KindSweep<typename LaneTraits<L>::S>& k,
                               size_t begin, size_t end, bool reverse) {
  if (k.record)
    sweep_batches<K, L, true>(x, k, begin, end, reverse);
  else
    sweep_batches<K, L, false>(x, k, begin, end, reverse);
}

/// The corrections of every lane of every batch of kind K, stored by constraint row.
template <class K, class L>
TB_PBD_INLINE void record_corrections(const typename LaneTraits<L>::S* x, const KindSweep<typename LaneTraits<L>::S>& k,
                                      const std::vector<int>& order, Eigen::MatrixXd& out) {
  using S = typename LaneTraits<L>::S;
  constexpr int N = K::kArity, W = LaneTraits<L>::W;
  size_t next = 0;  // position in `order` of the batch's lane 0
  for (size_t b = 0; b < k.layout.batch_count(); ++b) {
    Triple<L> p[N], corr[N];
    project_batch<K, L>(x, k, b, p, corr);
    S xyz[N][3][W];
    spill_corrections<L, static_cast<size_t>(N)>(corr, xyz);
    for (int j = 0; j < N; ++j)
      for (int l = 0; l < k.layout.count[b]; ++l)
        for (int d = 0; d < 3; ++d) out(order[next + static_cast<size_t>(l)], 3 * j + d) = xyz[j][d][l];
    next += static_cast<size_t>(k.layout.count[b]);
  }
}

// One function per instruction set, each with its target; SSE2 is every x86-64's.
#define TB_TARGET_AVX __attribute__((target("avx")))
#define TB_TARGET_AVX512VL __attribute__((target("avx512f,avx512dq,avx512vl")))
#define TB_TARGET_AVX512 __attribute__((target("avx512f,avx512dq")))
template <class K, class S>
void sweep_sse2(S* x, const KindSweep<S>& k, size_t begin, size_t end, bool reverse) {
  sweep_range<K, Lanes<InstructionSet::Sse2, S>>(x, k, begin, end, reverse);
}
template <class K, class S>
TB_TARGET_AVX void sweep_avx(S* x, const KindSweep<S>& k, size_t begin, size_t end, bool reverse) {
  sweep_range<K, Lanes<InstructionSet::Avx, S>>(x, k, begin, end, reverse);
}
template <class K, class S>
TB_TARGET_AVX512VL void sweep_avx512vl(S* x, const KindSweep<S>& k, size_t begin, size_t end, bool reverse) {
  sweep_range<K, Lanes<InstructionSet::Avx512Vl, S>>(x, k, begin, end, reverse);
}
template <class K, class S>
TB_TARGET_AVX512 void sweep_avx512(S* x, const KindSweep<S>& k, size_t begin, size_t end, bool reverse) {
  sweep_range<K, Lanes<InstructionSet::Avx512, S>>(x, k, begin, end, reverse);
}
template <class K, class S>
void corrections_sse2(const S* x, const KindSweep<S>& k, const std::vector<int>& order, Eigen::MatrixXd& out) {
  record_corrections<K, Lanes<InstructionSet::Sse2, S>>(x, k, order, out);
}
template <class K, class S>
TB_TARGET_AVX void corrections_avx(const S* x, const KindSweep<S>& k, const std::vector<int>& order,
                                   Eigen::MatrixXd& out) {
  record_corrections<K, Lanes<InstructionSet::Avx, S>>(x, k, order, out);
}
template <class K, class S>
TB_TARGET_AVX512VL void corrections_avx512vl(const S* x, const KindSweep<S>& k, const std::vector<int>& order,
                                             Eigen::MatrixXd& out) {
  record_corrections<K, Lanes<InstructionSet::Avx512Vl, S>>(x, k, order, out);
}
template <class K, class S>
TB_TARGET_AVX512 void corrections_avx512(const S* x, const KindSweep<S>& k, const std::vector<int>& order,
                                         Eigen::MatrixXd& out) {
  record_corrections<K, Lanes<InstructionSet::Avx512, S>>(x, k, order, out);
}
#undef TB_TARGET_AVX
#undef TB_TARGET_AVX512VL
#undef TB_TARGET_AVX512

/// Whether kind K turns a constraint's inverse masses into other numbers per slot
/// (a static `slot_weights(S* w)`, like stretch's shares).
template <class K, class S, class = void>
struct HasSlotWeights : std::false_type {};
template <class K, class S>
struct HasSlotWeights<K, S, std::void_t<decltype(K::slot_weights(std::declval<S*>()))>> : std::true_type {};
template <class K, class S>
void slot_weights(S* w) {
  if constexpr (HasSlotWeights<K, S>::value) K::slot_weights(w);
}

/// Kind K's kernels in precision S for every instruction set, in kInstructionSets' order.
template <class K, class S>
BatchKernels<S> batch_kernels() {
  static_assert(index(InstructionSet::Sse2) == 0 && index(InstructionSet::Avx) == 1 &&
                    index(InstructionSet::Avx512Vl) == 2 && index(InstructionSet::Avx512) == 3,
                "one function per instruction set, in the enumerators' order");
  return {{sweep_sse2<K, S>, sweep_avx<K, S>, sweep_avx512vl<K, S>, sweep_avx512<K, S>},
          {corrections_sse2<K, S>, corrections_avx<K, S>, corrections_avx512vl<K, S>, corrections_avx512<K, S>},
          slot_weights<K, S>};
}

}  // namespace tb::pbd::batches
