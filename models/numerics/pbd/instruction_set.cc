#include "instruction_set.h"

#include <algorithm>

namespace tb::pbd {

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

}  // namespace tb::pbd
