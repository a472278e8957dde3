// Which OpenBLAS kernels the FEM's factorisation runs on (CHOLMOD calls BLAS), and
// why tissuebench pins them: Debian's OpenBLAS picks its kernels for the CPU it
// finds at load time, and kernels for different CPUs sum in different orders, so
// the FEM-family fields differed in their last bits (up to about 1e-14 relative,
// 1e-10 for the iterative solves stopped at a tolerance) between two machines of
// the same kind whose CPUs differed (AMD Zen 4 got OpenBLAS's Cooperlake kernels,
// Zen 5 its Haswell/Zen ones). docs/determinism.md gives the measurements.
#pragma once

#include <string>

namespace tb {

/// The OpenBLAS kernel family every run uses where the CPU has its instructions
/// (AVX2 and FMA): the fields are then the same bits on every such x86-64 CPU.
inline constexpr const char* kPinnedBlasCore = "Haswell";

/// Called first in main: unless OPENBLAS_CORETYPE is set already (the user's
/// choice wins), and if the CPU has AVX2 and FMA, sets it to kPinnedBlasCore and
/// re-executes this program with the same arguments (OpenBLAS reads it when it is
/// loaded, before main). Returns only when no re-execution happens (or it failed:
/// then the run goes on with OpenBLAS's own choice, which run.json records).
void pin_blas_kernels(char** argv);

/// OpenBLAS's name of the kernels in use ("Haswell", "Cooperlake", ...).
std::string blas_core_name();

}  // namespace tb
