// The tests' main: OpenBLAS pinned to the kernels tissuebench itself runs on
// (experiments/blas_kernels.h), so a result at round-off level (a direct solve's last
// bits, an iteration stopped at its rounding floor) is the same on every CPU with
// AVX2 and FMA, as the runner's fields are. Unpinned, an AVX-512 CPU gets OpenBLAS's
// SkylakeX kernels and other last bits (docs/determinism.md).
#include <gtest/gtest.h>

#include "blas_kernels.h"

int main(int argc, char** argv) {
  tb::pin_blas_kernels(argv);  // re-executes this program once, with OPENBLAS_CORETYPE set
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
