// Runtime defaults of the sanitizers, linked into every executable of a TB_SANITIZE
// build (tb_project_target in CMakeLists.txt), so that GoogleTest's test discovery at
// build time, CTest and a hand-run binary behave alike. ASAN_OPTIONS, UBSAN_OPTIONS
// and LSAN_OPTIONS in the environment override them.
//
// - Leak detection off: OpenMPI, OpenBLAS and deal.II keep allocations to process
//   exit by design; leaks in the project's own code show up as growth in the
//   allocation-free-frames test (tests/models/allocation_free_frames_test.cc).
// - An allocation above 4 GiB is an error (a report and exit), not an attempt: no
//   test and no fuzz input needs that much, and a reader that asks for it from a
//   small file is a bug the fuzz targets must see (docs/robustness.md).
// - Every report prints a stack trace and exits non-zero; UBSan's too.

extern "C" {

const char* __asan_default_options() {
  return "detect_leaks=0:max_allocation_size_mb=4096:allocator_may_return_null=0:abort_on_error=0:"
         "strict_string_checks=1:detect_stack_use_after_return=0:check_initialization_order=1";
}

const char* __ubsan_default_options() { return "print_stacktrace=1:halt_on_error=1"; }

}  // extern "C"
