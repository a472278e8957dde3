// Arithmetic written once for a single number and for a batch of numbers (a GCC
// vector, one constraint per lane), in double or single precision, so that the
// PBD sweep, which projects a batch of independent constraints at a time, and the
// scalar constraint functions compute bitwise the same numbers. Every operation
// here is either exactly rounded (+ - * / sqrt) or a select, so a lane of a batch
// equals the scalar result of the same precision whatever the vector width; the
// build keeps FMA contraction off for the PBD files that use it (models/CMakeLists.txt),
// which would break that equality (and FMA measured 4% faster, 8% fewer
// instructions, on a 10k-vertex frame: not worth a second set of numbers). VBD's
// lanes (realtime/vbd_visit_blocks.h) are compiled for AVX2 with FMA contraction on:
// they need not equal a scalar path bitwise, only to round-off (their tests).
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>
#include <utility>

namespace tb::pbd {

// GCC does not inline the projection kernels on their own (too large), and as
// calls they cost a third of the sweep; in the batched sweep they must be inlined
// into the CPU-specific function to use its instruction set.
#define TB_PBD_INLINE inline __attribute__((always_inline))

namespace lanes {

/// W numbers of type S in one vector: a batch. +, -, *, / and comparisons act
/// lane by lane, comparisons giving a mask (-1 true, 0 false). Such vectors never
/// cross a call (the kernels are inlined into one function per instruction set),
/// so their ABI does not matter.
template <class S, int W>
struct VectorOf {
  typedef S type __attribute__((vector_size(W * sizeof(S))));
};
template <class S, int W>
using Vector = typename VectorOf<S, W>::type;

/// Four doubles (one AVX register): the batch of the double-precision kernels'
/// tests and of the scalar wrappers' lane count.
using Batch = Vector<double, 4>;
constexpr int kBatchWidth = 4;

/// Two doubles in one SSE2 register.
using Vector2 = Vector<double, 2>;

/// Two vectors acting as one of twice the lanes: a batch of four doubles as two
/// SSE2 registers. GCC's own 4-double vectors would do, but without AVX it lowers
/// their comparisons to scalar code (the PBD frame measured 2.3x slower than this).
template <class V>
struct Twin {
  V lo, hi;
};
#define TB_TWIN_BINARY(op)                                             \
  template <class V>                                                   \
  TB_PBD_INLINE auto operator op(const Twin<V>& a, const Twin<V>& b) { \
    return Twin<decltype(a.lo op b.lo)>{a.lo op b.lo, a.hi op b.hi};   \
  }                                                                    \
  template <class V>                                                   \
  TB_PBD_INLINE Twin<V> operator op(const Twin<V>& a, double b) {      \
    return {a.lo op b, a.hi op b};                                     \
  }                                                                    \
  template <class V>                                                   \
  TB_PBD_INLINE Twin<V> operator op(double a, const Twin<V>& b) {      \
    return {a op b.lo, a op b.hi};                                     \
  }
TB_TWIN_BINARY(+)
TB_TWIN_BINARY(-)
TB_TWIN_BINARY(*)
TB_TWIN_BINARY(/)
TB_TWIN_BINARY(<)
TB_TWIN_BINARY(>)
TB_TWIN_BINARY(&)
#undef TB_TWIN_BINARY
template <class V>
TB_PBD_INLINE Twin<V> operator-(const Twin<V>& a) {
  return {-a.lo, -a.hi};
}
template <class V>
TB_PBD_INLINE Twin<V>& operator+=(Twin<V>& a, const Twin<V>& b) {
  return a = a + b;
}

/// The number type of T: T itself for a number, the lanes' type for a batch.
template <class T, class = void>
struct ElementOf {
  using type = std::remove_cv_t<std::remove_reference_t<decltype(std::declval<T>()[0])>>;
};
template <class T>
struct ElementOf<T, std::enable_if_t<std::is_arithmetic_v<T>>> {
  using type = T;
};
template <class V>
struct ElementOf<Twin<V>> {
  using type = typename ElementOf<V>::type;
};
template <class T>
using Element = typename ElementOf<T>::type;

/// Lanes of T (1 for a number).
template <class T>
constexpr int width() {
  if constexpr (std::is_arithmetic_v<T>)
    return 1;
  else
    return static_cast<int>(sizeof(T) / sizeof(Element<T>));
}

/// The constant c in every lane (T{} is zero in every lane), rounded to T's precision.
template <class T>
TB_PBD_INLINE T splat(double c) {
  if constexpr (std::is_arithmetic_v<T>)
    return static_cast<T>(c);
  else
    return T{} + static_cast<Element<T>>(c);
}

/// m ? a : b, lane by lane for a batch (m from a comparison of batches).
template <class M, class T>
TB_PBD_INLINE T select(M m, T a, T b) {
  if constexpr (std::is_arithmetic_v<T>) {
    return m ? a : b;
  } else {  // as bit operations (and, andnot, or): GCC may lower a vector ?: to scalar code
    return reinterpret_cast<T>((m & reinterpret_cast<M>(a)) | (~m & reinterpret_cast<M>(b)));
  }
}

template <class T>
TB_PBD_INLINE T sqrt(T x) {
  if constexpr (std::is_arithmetic_v<T>) {
    return std::sqrt(x);
  } else {
    T r;  // one vsqrtpd / vsqrtps with -fno-math-errno (models/CMakeLists.txt)
    for (int l = 0; l < width<T>(); ++l) r[l] = std::sqrt(x[l]);
    return r;
  }
}

template <class T>
TB_PBD_INLINE T abs(T x) {
  if constexpr (std::is_arithmetic_v<T>) {
    return std::fabs(x);
  } else {  // clear the sign bits (the integer minimum's bit pattern): one instruction
    using Bits = decltype(x < x);
    const Bits sign = Bits{} + std::numeric_limits<Element<Bits>>::min();
    return reinterpret_cast<T>(reinterpret_cast<Bits>(x) & ~sign);
  }
}

/// Whether any lane of the mask m (from a comparison) is true.
template <class M>
TB_PBD_INLINE bool any(M m) {
  if constexpr (std::is_same_v<M, bool>) {
    return m;
  } else {  // one vptest or movmsk
    using Bits = Element<M>;
    Bits all{};
    for (int l = 0; l < width<M>(); ++l) all |= m[l];
    return all != 0;
  }
}

template <class M, class V>
TB_PBD_INLINE Twin<V> select(const Twin<M>& m, const Twin<V>& a, const Twin<V>& b) {
  return {select(m.lo, a.lo, b.lo), select(m.hi, a.hi, b.hi)};
}
template <class M>
TB_PBD_INLINE bool any(const Twin<M>& m) {
  return any(m.lo | m.hi);
}
template <class V>
TB_PBD_INLINE Twin<V> sqrt(const Twin<V>& x) {
  return {sqrt(x.lo), sqrt(x.hi)};
}
template <class V>
TB_PBD_INLINE Twin<V> abs(const Twin<V>& x) {
  return {abs(x.lo), abs(x.hi)};
}

/// atan2(y, x) in [-pi, pi], with the octant reduction done by selects so that it
/// vectorises; glibc's atan2 does not, and was 28% of a PBD frame. atan2(0, 0) = 0
/// (no NaN); y = -0 counts as positive. Double: Cephes' atan (S. Moshier, rational
/// minimax approximation on [0, 0.66], about 1e-16 relative). Single: Cephes'
/// atanf (polynomial on [0, tan(pi/8)], about 1 float ulp).
template <class T>
TB_PBD_INLINE T atan2(T y, T x) {
  using S = Element<T>;
  constexpr bool single = std::is_same_v<S, float>;
  constexpr double kPi = 3.14159265358979323846, kMoreBits = 6.123233995736765886130e-17;  // pi/2 - fl(pi/2)
  const T ax = abs(x), ay = abs(y);
  const auto steep = ay > ax;  // the angle is beyond pi/4: atan(a) = pi/2 - atan(1/a)
  const T num = select(steep, ax, ay), den = select(steep, ay, ax);  // a = num / den in [0, 1]
  // Beyond a = split, tan(pi/4 + z) = a gives z = (a - 1)/(a + 1) = (num - den)/(num + den).
  // One division either way; den = 0 only at the origin.
  const auto high = num > splat<T>(single ? 0.41421356237309504880 : 0.66) * den;
  const T one = splat<T>(1);
  const T z = select(high, num - den, num) / select(high, num + den, select(den > T{}, den, one));
  const T z2 = z * z;
  T small;  // atan(z)
  if constexpr (single) {
    const T p =
        ((splat<T>(8.05374449538e-2) * z2 - splat<T>(1.38776856032e-1)) * z2 + splat<T>(1.99777106478e-1)) * z2 -
        splat<T>(3.33329491539e-1);
    small = z + z * (z2 * p);
    T r = select(high, splat<T>(kPi / 4) + small, small);  // atan(a) in [0, pi/4]
    r = select(steep, splat<T>(kPi / 2) - r, r);           // [0, pi/2]
    r = select(x < T{}, splat<T>(kPi) - r, r);             // [0, pi]
    return select(y < T{}, -r, r);
  } else {
    const T p = (((splat<T>(-8.750608600031904122785e-1) * z2 - splat<T>(1.615753718733365076637e1)) * z2 -
                  splat<T>(7.500855792314704667340e1)) *
                     z2 -
                 splat<T>(1.228866684490136173410e2)) *
                    z2 -
                splat<T>(6.485021904942025371773e1);
    const T q = ((((z2 + splat<T>(2.485846490142306297962e1)) * z2 + splat<T>(1.650270098316988542046e2)) * z2 +
                  splat<T>(4.328810604912902668951e2)) *
                     z2 +
                 splat<T>(4.853903996359136964868e2)) *
                    z2 +
                splat<T>(1.945506571482613964425e2);
    small = z + z * (z2 * p / q);
    T r = select(high, splat<T>(kPi / 4) + (small + splat<T>(0.5 * kMoreBits)), small);  // atan(a) in [0, pi/4]
    r = select(steep, splat<T>(kPi / 2) - r + splat<T>(kMoreBits), r);                   // [0, pi/2]
    r = select(x < T{}, splat<T>(kPi) - r + splat<T>(2 * kMoreBits), r);                 // [0, pi]
    return select(y < T{}, -r, r);
  }
}

/// ln x for a positive, finite, normal x in double precision, written with selects
/// and bit operations so that it vectorises (glibc's log does not, and was a tenth of
/// a Vertex Block Descent frame). The reduction and polynomial of fdlibm's e_log.c
/// (Sun Microsystems 1993): x = 2^k m, m in [sqrt(2)/2, sqrt(2)), f = m - 1,
/// s = f / (2 + f), ln m = f - s (f - R(s^2)) with the minimax R of degree 14 below
/// (error under 2^-58.45 on that interval), ln 2 split in a high part exact in k ln2_hi.
/// Subnormal x are scaled by 2^54 first. Within 1 ulp of the C library
/// (tests/models/numerics/pbd/constraint_batches_test.cc; with AVX2 and FMA:
/// tests/models/realtime/vbd_kernels_test.cc). Zero, negative, infinite or NaN x: an
/// unspecified finite or NaN number (the caller rules them out; VBD checks det F > 0 first).
template <class T>
TB_PBD_INLINE T log(T x) {
  static_assert(std::is_same_v<Element<T>, double>, "lanes::log is written for double precision");
  constexpr double kLn2Hi = 6.93147180369123816490e-01, kLn2Lo = 1.90821492927058770002e-10;
  constexpr double kLg1 = 6.666666666666735130e-01, kLg2 = 3.999999999940941908e-01,
                   kLg3 = 2.857142874366239149e-01, kLg4 = 2.222219843214978396e-01,
                   kLg5 = 1.818357216161805012e-01, kLg6 = 1.531383769920937332e-01,
                   kLg7 = 1.479819860511658591e-01;
  // A subnormal x times 2^54 is normal; k below takes the 54 back.
  const auto subnormal = x < splat<T>(std::numeric_limits<double>::min());
  x = select(subnormal, x * splat<T>(18014398509481984.0), x);
  // The biased exponent e and the mantissa m in [1, 2), by bits; e as a double by
  // the 2^52 trick (no int64-to-double instruction before AVX-512DQ).
  T m, e;
  if constexpr (std::is_arithmetic_v<T>) {
    std::uint64_t bits;
    std::memcpy(&bits, &x, sizeof bits);
    const std::uint64_t mbits = (bits & 0x000fffffffffffffULL) | 0x3ff0000000000000ULL,
                        ebits = (bits >> 52) | 0x4330000000000000ULL;
    std::memcpy(&m, &mbits, sizeof m);
    std::memcpy(&e, &ebits, sizeof e);
  } else {
    using Bits = decltype(x < x);  // signed 64-bit lanes
    const Bits bits = reinterpret_cast<Bits>(x);
    const Bits exponent = (bits >> 52) & 0x7ff;
    m = reinterpret_cast<T>((bits & 0x000fffffffffffffLL) | 0x3ff0000000000000LL);
    e = reinterpret_cast<T>(exponent | 0x4330000000000000LL);
  }
  const T one = splat<T>(1);
  const auto high = m > splat<T>(1.41421356237309504880);
  m = select(high, splat<T>(0.5) * m, m);  // exact
  const T k = (e - splat<T>(4503599627370496.0 + 1023)) + select(high, one, T{}) - select(subnormal, splat<T>(54), T{});
  const T f = m - one, s = f / (splat<T>(2) + f), z = s * s, w = z * z;
  const T t1 = w * (splat<T>(kLg2) + w * (splat<T>(kLg4) + w * splat<T>(kLg6)));
  const T t2 = z * (splat<T>(kLg1) + w * (splat<T>(kLg3) + w * (splat<T>(kLg5) + w * splat<T>(kLg7))));
  const T hfsq = splat<T>(0.5) * f * f;
  return k * splat<T>(kLn2Hi) - ((hfsq - (s * (hfsq + (t1 + t2)) + k * splat<T>(kLn2Lo))) - f);
}
template <class V>
TB_PBD_INLINE Twin<V> log(const Twin<V>& x) {
  return {log(x.lo), log(x.hi)};
}

/// A 3-vector of numbers or of batches (one vector per lane).
template <class T>
struct Triple {
  T x, y, z;
};
template <class T>
TB_PBD_INLINE Triple<T> operator+(const Triple<T>& a, const Triple<T>& b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
template <class T>
TB_PBD_INLINE Triple<T> operator-(const Triple<T>& a, const Triple<T>& b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
template <class T>
TB_PBD_INLINE Triple<T> operator*(T s, const Triple<T>& a) {
  return {s * a.x, s * a.y, s * a.z};
}
template <class T>
TB_PBD_INLINE T dot(const Triple<T>& a, const Triple<T>& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <class T>
TB_PBD_INLINE Triple<T> cross(const Triple<T>& a, const Triple<T>& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

}  // namespace lanes
}  // namespace tb::pbd
