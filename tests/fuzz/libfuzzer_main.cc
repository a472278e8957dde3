// The libFuzzer entry point of one fuzz target (TB_FUZZ_TARGET, set per binary by
// tests/fuzz/CMakeLists.txt with -DTB_LIBFUZZER=ON). A contract violation aborts,
// which libFuzzer records as a crash with its input; crashes, sanitizer reports,
// hangs (-timeout) and allocations beyond -malloc_limit_mb it catches itself.
//   build-fuzz/tests/fuzz/fuzz_obj -dict=DICT -timeout=10 -rss_limit_mb=4096 CORPUS_COPY tests/fuzz/corpus/obj
#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include "fuzz_targets.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const tb::fuzz::Target& target = tb::fuzz::find_target(TB_FUZZ_TARGET);
  static const tb::fuzz::Workspace workspace(target.companions ? TB_FUZZ_AUX_DIR : "");
  const tb::fuzz::Outcome out =
      tb::fuzz::run_input(target, std::string(reinterpret_cast<const char*>(data), size), workspace);
  if (out.kind == tb::fuzz::Outcome::Kind::Finding) {
    std::fprintf(stderr, "tb fuzz target %s: FINDING: %s\n", target.name.c_str(), out.message.c_str());
    std::abort();
  }
  return 0;
}
