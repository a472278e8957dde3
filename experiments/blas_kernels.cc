#include "blas_kernels.h"

#include <unistd.h>

#include <cstdlib>

extern "C" char* openblas_get_corename(void);  // libopenblas, linked explicitly

namespace tb {

void pin_blas_kernels(char** argv) {
  if (std::getenv("OPENBLAS_CORETYPE")) return;
  __builtin_cpu_init();
  if (!__builtin_cpu_supports("avx2") || !__builtin_cpu_supports("fma")) return;
  if (setenv("OPENBLAS_CORETYPE", kPinnedBlasCore, 1) != 0) return;
  execv("/proc/self/exe", argv);  // only returns on failure
}

std::string blas_core_name() {
  const char* name = openblas_get_corename();
  return name ? name : "unknown";
}

}  // namespace tb
