// The vector instructions and the number type a batched PBD sweep runs with,
// chosen at run time: which ones exist, which this CPU has, and how many
// constraints a batch holds on each. The kernels compiled for each one are chosen
// from a kind's table of them (batch_kernels.h).
#pragma once

#include <cstddef>

namespace tb::pbd {

/// The vector instructions a sweep runs with, chosen at run time: SSE2 (every
/// x86-64), AVX, AVX-512VL (AVX's 256-bit batches with AVX-512's 32 vector
/// registers: the bending kernel spills less) or AVX-512 (F and DQ, 512-bit
/// batches). In double precision every one gives the same numbers; single
/// precision gives its own (the same on every one).
enum class InstructionSet { Sse2, Avx, Avx512Vl, Avx512 };
/// Every instruction set, whether this CPU has it or not (cpu_supports), in the
/// enumerators' order: kInstructionSets[index(isa)] == isa.
constexpr InstructionSet kInstructionSets[] = {InstructionSet::Sse2, InstructionSet::Avx, InstructionSet::Avx512Vl,
                                               InstructionSet::Avx512};
constexpr size_t kInstructionSetCount = sizeof(kInstructionSets) / sizeof(kInstructionSets[0]);
constexpr size_t index(InstructionSet isa) { return static_cast<size_t>(isa); }

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
/// differs from double's by rounding: docs/scaling.md, pbd_solver.h).
enum class Precision { Double, Single };
const char* name(Precision precision);
/// The precision of the number type S (double or float).
template <class S>
constexpr Precision precision_of() {
  return sizeof(S) == sizeof(float) ? Precision::Single : Precision::Double;
}
/// Of a thing held once per precision, the one for S.
template <class S, class Double, class Single>
constexpr const auto& for_precision(const Double& double_one, const Single& single_one) {
  if constexpr (precision_of<S>() == Precision::Single)
    return single_one;
  else
    return double_one;
}

/// Constraints per batch: one per lane of the instruction set's vectors (SSE2
/// double: two registers of two).
int batch_width(InstructionSet isa, Precision precision);

}  // namespace tb::pbd
