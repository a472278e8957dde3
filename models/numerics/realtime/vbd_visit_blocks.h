// Vertex Block Descent's per-vertex terms four tets at a time: a vertex's tets laid
// out in blocks of four, one tet per lane of a vector (structure of arrays), and the
// kernel that sums their force and stiffness into the vertex's 3x3 Newton system
// (vbd_solve.cc's update_vertex, Chen et al. 2024 eqs. 7-8) with the law's
// lane_node_terms (neo_hookean.h). The scalar path computes the same sums one tet at
// a time; the two agree to round-off (tests/models/realtime/vbd_kernels_test.cc) and
// the batched one is about three times as fast (docs/realtime_nonlinear.md, "Four
// tets at a time").
//
// F of a lane is sum_j (x_j - x_v) g_j^T over the tet's three other nodes j: tet_F
// with the vertex's own gradient taken as minus the others' sum, which the block
// stores as g_v (vbd_solve.cc), so that F moves with the vertex exactly by dx g_v^T
// and det F by dx . cof(F) g_v (the positivity check's lemma). A vertex's last block is padded with
// empty lanes: volume 0, g 0, its own index for the other nodes, and F = I, so that
// they add nothing and never look inverted.
#pragma once

#include <Eigen/Core>
#include <type_traits>
#include <utility>

#include "batch_gather.h"
#include "lane_math.h"

namespace tb {

/// Lanes of a visit block.
constexpr int kVisitLanes = 4;

/// Four of a vertex's tets, one per lane.
struct alignas(32) VisitBlock {
  double g[4][3][kVisitLanes]{};    ///< [node][coordinate][lane]: node 0 the vertex's shape gradient, 1..3 the others', 1/m
  double volume[kVisitLanes]{};     ///< rest volume, m^3 (0 in an empty lane)
  double empty[kVisitLanes]{};      ///< 1 in an empty lane (F = I there), else 0
  int other[3][kVisitLanes]{};      ///< the tet's other nodes in the tet's order (the vertex itself in an empty lane)
};

/// Of one block, lane by lane, cof(F) g and det F: moving the vertex by dx makes
/// det F exactly J + dx . c (the matrix determinant lemma; vbd_solve.cc). Aligned
/// to 32 bytes explicitly: a GCC vector type of 32 bytes declared outside an AVX
/// function has an alignment of 16 only, so an array of it (as a container allocates
/// it) would not suit the AVX code's aligned moves (a test crashed on one).
template <class L>
struct alignas(32) BlockDeterminants {
  L c[3];
  L J;
};

/// Whether Law offers the batched node terms (lane_node_terms) the kernel needs.
template <class Law, class = void>
struct HasLaneNodeTerms : std::false_type {};
template <class Law>
struct HasLaneNodeTerms<
    Law, std::void_t<decltype(std::declval<const Law&>().template lane_node_terms<double>(
             std::declval<const double (&)[3][3]>(), std::declval<const double (&)[3][3]>(), std::declval<const double&>(),
             std::declval<const double (&)[3]>(), std::declval<double (&)[3]>(), std::declval<double (&)[3]>(),
             std::declval<double&>(), std::declval<double&>()))>> : std::true_type {};

namespace visit_lanes {

using pbd::lanes::splat;

template <class L>
TB_PBD_INLINE L load(const double* p) {
  return pbd::batches::load_lanes<L>(p);
}

/// Lane l of v.
template <class L>
TB_PBD_INLINE double lane(const L& v, int l) {
  if constexpr (std::is_same_v<L, pbd::batches::SseLanes>)
    return l < 2 ? v.lo[l] : v.hi[l - 2];
  else
    return v[l];
}

/// The sum of v's lanes, in lane order (deterministic).
template <class L>
TB_PBD_INLINE double sum(const L& v) {
  return (lane(v, 0) + lane(v, 1)) + (lane(v, 2) + lane(v, 3));
}

/// Coordinate r of the four lanes' nodes q[0..3] of positions x (3 by #V, column-major).
template <class L>
TB_PBD_INLINE L gather(const double* x, const int* q, int r) {
  const double a = x[3 * q[0] + r], b = x[3 * q[1] + r], c = x[3 * q[2] + r], d = x[3 * q[3] + r];
  if constexpr (std::is_same_v<L, pbd::batches::SseLanes>)
    return L{pbd::lanes::Vector2{a, b}, pbd::lanes::Vector2{c, d}};
  else
    return L{a, b, c, d};
}

/// Whether every lane of v is above `bound` (false for a NaN lane).
template <class L>
TB_PBD_INLINE bool all_above(const L& v, double bound) {
  if constexpr (std::is_same_v<L, pbd::batches::SseLanes>)
    return all_above(v.lo, bound) && all_above(v.hi, bound);
  else
    return !pbd::lanes::any(~(v > splat<L>(bound)));
}

/// F (and its cofactor) of the block's lanes with the vertex at xv.
template <class L>
TB_PBD_INLINE void deformation_gradients(const VisitBlock& b, const double* x, const double (&xv)[3], L (&F)[3][3]) {
  L d[3][3];  // d[j][r]: coordinate r of other node j minus the vertex's
  for (int j = 0; j < 3; ++j)
    for (int r = 0; r < 3; ++r) d[j][r] = gather<L>(x, b.other[j], r) - splat<L>(xv[r]);
  const L empty = load<L>(b.empty);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) {
      F[r][c] = d[0][r] * load<L>(b.g[1][c]) + d[1][r] * load<L>(b.g[2][c]) + d[2][r] * load<L>(b.g[3][c]);
      if (r == c) F[r][c] = F[r][c] + empty;
    }
}

/// cof F, column k the cross product of F's other two columns (so J = F.col(0) . C.col(0)).
template <class L>
TB_PBD_INLINE void cofactor(const L (&F)[3][3], L (&C)[3][3]) {
  for (int k = 0; k < 3; ++k) {
    const int a = (k + 1) % 3, b = (k + 2) % 3;
    C[0][k] = F[1][a] * F[2][b] - F[2][a] * F[1][b];
    C[1][k] = F[2][a] * F[0][b] - F[0][a] * F[2][b];
    C[2][k] = F[0][a] * F[1][b] - F[1][a] * F[0][b];
  }
}

}  // namespace visit_lanes

/// The vertex's tets' share of its Newton system, block by block: gradient +=
/// sum V P(F) g and H += sum V node_stiffness(F, g) over the `count` blocks at
/// `blocks`, with the vertex at xv and the others at x (3 by #V, column-major); the
/// per-lane (cof(F) g, det F) into dets[0 .. count) if dets is not null. Returns -1,
/// or the lane (4 block + lane) of the first tet whose det F is not positive, where
/// it stops with the sums incomplete (the caller hands that tet to the law's scalar
/// node terms, whose error names the law). Inlined into the caller's per-instruction-set
/// function.
template <class L, class Law>
TB_PBD_INLINE int add_block_terms(const Law& law, const VisitBlock* blocks, int count, const double* x,
                                  const Eigen::Vector3d& xv, Eigen::Vector3d& gradient, Eigen::Matrix3d& H,
                                  BlockDeterminants<L>* dets) {
  namespace V = visit_lanes;
  const double at[3] = {xv(0), xv(1), xv(2)};
  L sum_f[3] = {}, sum_cc[6] = {}, sum_I = {};  // sum_cc: the upper triangle of sum V s_cc c c^T, row by row
  for (int k = 0; k < count; ++k) {
    const VisitBlock& b = blocks[k];
    L F[3][3], C[3][3];
    V::deformation_gradients<L>(b, x, at, F);
    V::cofactor<L>(F, C);
    const L J = F[0][0] * C[0][0] + F[1][0] * C[1][0] + F[2][0] * C[2][0];
    if (!V::all_above<L>(J, 0))  // lanes::log takes any positive J, subnormal ones too
      for (int l = 0; l < kVisitLanes; ++l)
        if (!(V::lane(J, l) > 0)) return kVisitLanes * k + l;
    const L g[3] = {V::load<L>(b.g[0][0]), V::load<L>(b.g[0][1]), V::load<L>(b.g[0][2])};
    L force[3], c[3], s_cc, s_I;
    law.lane_node_terms(F, C, J, g, force, c, s_cc, s_I);
    const L volume = V::load<L>(b.volume);
    for (int i = 0; i < 3; ++i) sum_f[i] = sum_f[i] + volume * force[i];
    const L w = volume * s_cc;
    const L wc[3] = {w * c[0], w * c[1], w * c[2]};
    sum_cc[0] = sum_cc[0] + wc[0] * c[0];
    sum_cc[1] = sum_cc[1] + wc[0] * c[1];
    sum_cc[2] = sum_cc[2] + wc[0] * c[2];
    sum_cc[3] = sum_cc[3] + wc[1] * c[1];
    sum_cc[4] = sum_cc[4] + wc[1] * c[2];
    sum_cc[5] = sum_cc[5] + wc[2] * c[2];
    sum_I = sum_I + volume * s_I;
    if (dets) dets[k] = {{c[0], c[1], c[2]}, J};
  }
  for (int i = 0; i < 3; ++i) gradient(i) += V::sum(sum_f[i]);
  const double diagonal = V::sum(sum_I);
  for (int i = 0, n = 0; i < 3; ++i)
    for (int j = i; j < 3; ++j, ++n) {
      const double h = V::sum(sum_cc[n]);
      H(i, j) += h + (i == j ? diagonal : 0);
      if (j != i) H(j, i) += h;
    }
  return -1;
}

/// Whether every lane of the `count` blocks keeps det F above `bound` after the
/// vertex moves by dx, from their (cof(F) g, det F) (add_block_terms).
template <class L>
TB_PBD_INLINE bool blocks_stay_above(const BlockDeterminants<L>* dets, int count, const Eigen::Vector3d& dx,
                                     double bound) {
  using visit_lanes::splat;
  const L d0 = splat<L>(dx(0)), d1 = splat<L>(dx(1)), d2 = splat<L>(dx(2));
  for (int k = 0; k < count; ++k) {
    const BlockDeterminants<L>& e = dets[k];
    if (!visit_lanes::all_above<L>(e.J + (d0 * e.c[0] + d1 * e.c[1] + d2 * e.c[2]), bound)) return false;
  }
  return true;
}

/// The same as blocks_stay_above, recomputing each lane's det F with the vertex at
/// `at` (for a vertex in more blocks than its caller caches).
template <class L>
TB_PBD_INLINE bool blocks_above_at(const VisitBlock* blocks, int count, const double* x, const Eigen::Vector3d& at,
                                   double bound) {
  const double xv[3] = {at(0), at(1), at(2)};
  for (int k = 0; k < count; ++k) {
    L F[3][3], C[3][3];
    visit_lanes::deformation_gradients<L>(blocks[k], x, xv, F);
    visit_lanes::cofactor<L>(F, C);
    if (!visit_lanes::all_above<L>(F[0][0] * C[0][0] + F[1][0] * C[1][0] + F[2][0] * C[2][0], bound)) return false;
  }
  return true;
}

}  // namespace tb
