// The libFuzzer entry point of one fuzz target (TB_FUZZ_TARGET, set per binary by
// tests/fuzz/CMakeLists.txt with -DTB_LIBFUZZER=ON). A contract violation aborts,
// which libFuzzer records as a crash with its input; crashes, sanitizer reports,
// hangs (-timeout) and allocations beyond -malloc_limit_mb it catches itself.
//   build-fuzz/tests/fuzz/fuzz_obj -dict=DICT -timeout=10 -rss_limit_mb=4096 CORPUS_COPY tests/fuzz/corpus/obj
// With TB_LIBFUZZER_REPORT=FILE.json in the environment, the binary writes at exit
// what the deterministic driver reports (tb_fuzz --report): inputs run, accepted,
// rejected, distinct error messages (message_kind) and the slowest input, timed
// around the target alone (scripts/fuzz_libfuzzer collects these).
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <string>

#include "fuzz_targets.h"

namespace {

struct Stats {
  long inputs = 0, accepted = 0, rejected = 0;
  std::map<std::string, long> kinds;
  double slowest_ms = 0;
  size_t slowest_bytes = 0;
  std::string slowest_outcome;
};

// Never destroyed: write_report runs at exit, after function-local statics that were
// constructed after its registration are gone.
Stats& stats() {
  static Stats* s = new Stats;
  return *s;
}

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (unsigned char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += static_cast<char>(c);
    } else if (c < 0x20 || c >= 0x7f) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", c);
      out += buf;
    } else {
      out += static_cast<char>(c);
    }
  }
  return out + "\"";
}

void write_report() {
  const char* path = std::getenv("TB_LIBFUZZER_REPORT");
  if (!path || !*path) return;
  const Stats& s = stats();
  std::ofstream out(path);
  out << "{\"target\": " << json_string(TB_FUZZ_TARGET) << ", \"inputs\": " << s.inputs
      << ", \"accepted\": " << s.accepted << ", \"rejected\": " << s.rejected
      << ", \"distinct_messages\": " << s.kinds.size() << ", \"slowest_ms\": " << s.slowest_ms
      << ", \"slowest_input_bytes\": " << s.slowest_bytes << ", \"slowest_outcome\": " << json_string(s.slowest_outcome)
      << ", \"messages\": {";
  bool first = true;
  for (const auto& [kind, count] : s.kinds) {
    out << (first ? "" : ", ") << json_string(kind) << ": " << count;
    first = false;
  }
  out << "}}\n";
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const tb::fuzz::Target& target = tb::fuzz::find_target(TB_FUZZ_TARGET);
  static const tb::fuzz::Workspace workspace(target.companions ? TB_FUZZ_AUX_DIR : "");
  static const bool registered = std::atexit(write_report) == 0;
  (void)registered;
  const auto start = std::chrono::steady_clock::now();
  const tb::fuzz::Outcome out =
      tb::fuzz::run_input(target, std::string(reinterpret_cast<const char*>(data), size), workspace);
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  if (out.kind == tb::fuzz::Outcome::Kind::Finding) {
    std::fprintf(stderr, "tb fuzz target %s: FINDING: %s\n", target.name.c_str(), out.message.c_str());
    std::abort();
  }
  Stats& s = stats();
  ++s.inputs;
  if (ms > s.slowest_ms) {
    s.slowest_ms = ms;
    s.slowest_bytes = size;
    s.slowest_outcome = out.kind == tb::fuzz::Outcome::Kind::Accepted ? "accepted" : out.message;
  }
  if (out.kind == tb::fuzz::Outcome::Kind::Accepted)
    ++s.accepted;
  else
    ++s.rejected, ++s.kinds[tb::fuzz::message_kind(out.message, workspace.dir() + "/")];
  return 0;
}
