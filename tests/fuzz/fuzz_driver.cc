// tb_fuzz: the deterministic fuzz driver (docs/robustness.md). For each target it
// runs the committed seeds (tests/fuzz/corpus/<target>/) as they are, then --runs
// mutated inputs from the seeded mutator (mutator.h), each under a time limit, and
// judges every outcome by the readers' contract (fuzz_targets.h). A contract
// violation is saved to --findings and counted; a crash, a sanitizer report or a
// hang stops the run after saving the input that caused it. Exit status 0 only when
// there was no finding.
//
//   tb_fuzz --corpus tests/fuzz/corpus [--target obj ...] [--runs 2000] [--seed 1]
//           [--time-limit 10] [--findings DIR] [--report FILE.json] [--markdown FILE.md]
//   tb_fuzz --target obj --replay FILE...      one input each, as libFuzzer's binary would
//   tb_fuzz --replay-dir DIR                   DIR/<target>/*: the past findings (regressions)
//   tb_fuzz --target obj --input-index K ...   write the K-th input of a run to stdout
//   tb_fuzz --list | --write-dictionaries DIR
#include <fcntl.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <condition_variable>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <thread>

#include "fuzz_targets.h"
#include "mutator.h"

#if defined(__SANITIZE_ADDRESS__)
#define TB_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define TB_ASAN 1
#endif
#endif
#ifdef TB_ASAN
#include <sanitizer/common_interface_defs.h>
#endif

namespace tb::fuzz {
namespace {
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// ---- the input being run, for the crash and hang handlers ------------------------
// A crash handler may only use async-signal-safe calls: the path is prepared before
// each input, and the bytes are written with open/write/close.
char g_crash_path[4096] = {};
const std::string* g_current = nullptr;

void save_current_input() {
  if (!g_current || !g_crash_path[0]) return;
  const int fd = ::open(g_crash_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (fd < 0) return;
  size_t done = 0;
  while (done < g_current->size()) {
    const ssize_t n = ::write(fd, g_current->data() + done, g_current->size() - done);
    if (n <= 0) break;
    done += static_cast<size_t>(n);
  }
  ::close(fd);
  const char note[] = "tb_fuzz: the input that crashed is saved to ";
  [[maybe_unused]] ssize_t w = ::write(2, note, sizeof note - 1);
  w = ::write(2, g_crash_path, std::strlen(g_crash_path));
  w = ::write(2, "\n", 1);
}

void on_fatal_signal(int sig) {
  save_current_input();
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

/// Stops the process when one input runs longer than the limit (a hang).
class Watchdog {
 public:
  explicit Watchdog(double limit_s) : limit_(limit_s), thread_([this] { watch(); }) {}
  ~Watchdog() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    cv_.notify_all();
    thread_.join();
  }
  void start(const std::string& what) {
    std::lock_guard<std::mutex> lock(mutex_);
    what_ = what;
    started_ = Clock::now();
    running_ = true;
  }
  void done() {
    std::lock_guard<std::mutex> lock(mutex_);
    running_ = false;
  }

 private:
  void watch() {
    std::unique_lock<std::mutex> lock(mutex_);
    while (!stop_) {
      cv_.wait_for(lock, std::chrono::milliseconds(100));
      if (running_ && std::chrono::duration<double>(Clock::now() - started_).count() > limit_) {
        std::cerr << "tb_fuzz: FINDING (hang): " << what_ << " ran longer than " << limit_ << " s\n";
        save_current_input();
        std::_Exit(3);
      }
    }
  }
  double limit_;
  std::mutex mutex_;
  std::condition_variable cv_;
  bool stop_ = false, running_ = false;
  std::string what_;
  Clock::time_point started_;
  std::thread thread_;
};

std::string read_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// The seed files of a target, in name order.
std::vector<std::string> load_corpus(const fs::path& dir) {
  std::vector<fs::path> files;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (e.is_regular_file()) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  std::vector<std::string> out;
  for (const auto& f : files) out.push_back(read_bytes(f));
  return out;
}

struct Stats {
  long inputs = 0, accepted = 0, rejected = 0, findings = 0;
  std::set<std::string> kinds;
  std::map<std::string, long> kind_count;
  double slowest_ms = 0, total_s = 0;
  long slowest_index = -1;
  size_t slowest_size = 0;
  std::string slowest_outcome;
};

struct Options {
  std::vector<std::string> targets;
  long runs = 1000;
  uint64_t seed = 1;
  std::string corpus, findings = "fuzz-findings", report, markdown, replay_dir, dictionaries;
  std::vector<std::string> replay;
  double time_limit = 10;
  long input_index = -1;
  bool list = false;
};

std::string finding_path(const Options& o, const Target& t, const std::string& tag) {
  const fs::path dir = fs::path(o.findings) / t.name;
  fs::create_directories(dir);
  return (dir / tag).string();
}

void prepare_crash_path(const std::string& path) {
  std::snprintf(g_crash_path, sizeof g_crash_path, "%s", path.c_str());
}

/// Runs one input; updates the statistics; returns false on a finding.
bool run_one(const Options& o, const Target& t, const Workspace& w, Watchdog& dog, const std::string& input, long index,
             Stats& st) {
  g_current = &input;
  const auto start = Clock::now();
  dog.start(t.name + " input " + std::to_string(index));
  const Outcome out = run_input(t, input, w);
  dog.done();
  const double ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  g_current = nullptr;
  ++st.inputs;
  st.total_s += ms / 1000;
  if (ms > st.slowest_ms) {
    st.slowest_ms = ms;
    st.slowest_index = index;
    st.slowest_size = input.size();
    st.slowest_outcome = out.kind == Outcome::Kind::Accepted ? "accepted" : out.message;
  }
  if (out.kind == Outcome::Kind::Accepted) {
    ++st.accepted;
    return true;
  }
  if (out.kind == Outcome::Kind::Rejected) {
    ++st.rejected;
    const std::string kind = message_kind(out.message, w.dir() + "/");
    st.kinds.insert(kind);
    ++st.kind_count[kind];
    return true;
  }
  ++st.findings;
  const std::string saved = finding_path(o, t, "finding-" + std::to_string(index));
  std::ofstream(saved, std::ios::binary) << input;
  std::cerr << "tb_fuzz: FINDING: " << t.name << " input " << index << ": " << out.message << " (input saved to "
            << saved << ")\n";
  return false;
}

/// The K-th input of a run: K < #seeds is seed K, then the mutations.
class InputSequence {
 public:
  InputSequence(const Options& o, const Target& t, std::vector<std::string> corpus)
      : corpus_(std::move(corpus)), mutator_(o.seed ^ hash_name(t.name), t.dictionary) {}
  std::string input(long k) {
    if (k < static_cast<long>(corpus_.size())) return corpus_[static_cast<size_t>(k)];
    const std::string& base = corpus_[mutator_.below(corpus_.size())];
    return mutator_.mutate(base, corpus_);
  }
  size_t seeds() const { return corpus_.size(); }

 private:
  std::vector<std::string> corpus_;
  Mutator mutator_;
};

int usage(const std::string& problem) {
  std::cerr << "tb_fuzz: " << problem << " (see the comment at the top of tests/fuzz/fuzz_driver.cc)\n";
  return 2;
}

std::string dictionary_entry(const std::string& word) {
  std::ostringstream os;
  os << '"';
  for (unsigned char c : word) {
    if (c == '"' || c == '\\')
      os << '\\' << c;
    else if (c < 32 || c > 126)
      os << "\\x" << std::hex << std::setw(2) << std::setfill('0') << static_cast<int>(c) << std::dec;
    else
      os << c;
  }
  os << '"';
  return os.str();
}

int main_impl(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::invalid_argument(a + " needs a value");
      return argv[++i];
    };
    if (a == "--target")
      o.targets.push_back(value());
    else if (a == "--runs")
      o.runs = std::stol(value());
    else if (a == "--seed")
      o.seed = std::stoull(value());
    else if (a == "--corpus")
      o.corpus = value();
    else if (a == "--time-limit")
      o.time_limit = std::stod(value());
    else if (a == "--findings")
      o.findings = value();
    else if (a == "--report")
      o.report = value();
    else if (a == "--markdown")
      o.markdown = value();
    else if (a == "--replay-dir")
      o.replay_dir = value();
    else if (a == "--input-index")
      o.input_index = std::stol(value());
    else if (a == "--write-dictionaries")
      o.dictionaries = value();
    else if (a == "--list")
      o.list = true;
    else if (a == "--replay")
      while (i + 1 < argc && std::string(argv[i + 1]).rfind("--", 0) != 0) o.replay.push_back(argv[++i]);
    else
      return usage("unknown argument '" + a + "'");
  }
  if (o.list) {
    for (const Target& t : targets()) std::cout << t.name << ": " << t.description << "\n";
    return 0;
  }
  if (!o.dictionaries.empty()) {
    fs::create_directories(o.dictionaries);
    for (const Target& t : targets()) {
      std::ofstream out(fs::path(o.dictionaries) / (t.name + ".dict"));
      for (const std::string& w : t.dictionary) out << dictionary_entry(w) << "\n";
    }
    return 0;
  }
  std::vector<const Target*> chosen;
  for (const std::string& name : o.targets) chosen.push_back(&find_target(name));
  if (chosen.empty())
    for (const Target& t : targets()) chosen.push_back(&t);
  const std::string aux = o.corpus.empty() ? "" : (fs::path(o.corpus) / "scenario_aux").string();

  // A finding of a crash saves the input before the process ends.
  for (int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT}) std::signal(sig, on_fatal_signal);
#ifdef TB_ASAN
  __sanitizer_set_death_callback(save_current_input);
#else
  // The allocation bound of an uninstrumented build (a sanitized one has ASan's
  // max_allocation_size_mb, tests/sanitizer_defaults.cc): 8 GiB of address space, so
  // an allocation sized by a header count fails as std::bad_alloc, a finding.
  const rlimit limit{8ull << 30, 8ull << 30};
  setrlimit(RLIMIT_AS, &limit);
#endif

  Watchdog dog(o.time_limit);
  if (!o.replay.empty() || !o.replay_dir.empty()) {
    // Each file through its target: the past findings must now be accepted or rejected cleanly.
    std::vector<std::pair<const Target*, fs::path>> inputs;
    if (!o.replay_dir.empty()) {
      for (const Target& t : targets()) {
        std::error_code ec;
        std::vector<fs::path> files;
        for (const auto& e : fs::directory_iterator(fs::path(o.replay_dir) / t.name, ec))
          if (e.is_regular_file()) files.push_back(e.path());
        std::sort(files.begin(), files.end());
        for (const auto& f : files) inputs.emplace_back(&t, f);
      }
    }
    if (!o.replay.empty() && chosen.size() != 1) return usage("--replay needs one --target");
    for (const std::string& f : o.replay) inputs.emplace_back(chosen[0], f);
    int findings = 0;
    for (const auto& [t, file] : inputs) {
      Workspace w(t->companions ? aux : "");
      prepare_crash_path(finding_path(o, *t, "crash-replay"));
      Stats st;
      const std::string input = read_bytes(file);
      const bool ok = run_one(o, *t, w, dog, input, 0, st);
      findings += !ok;
      std::cout << t->name << " " << file.string() << ": "
                << (!ok           ? "FINDING"
                    : st.accepted ? "accepted"
                                  : "rejected: " + *st.kinds.begin())
                << "\n";
    }
    std::cout << inputs.size() << " inputs replayed, " << findings << " findings\n";
    return findings ? 1 : 0;
  }
  if (o.corpus.empty()) return usage("--corpus is required");

  nlohmann::json report = nlohmann::json::object();
  long total_findings = 0;
  for (const Target* t : chosen) {
    std::vector<std::string> corpus = load_corpus(fs::path(o.corpus) / t->name);
    if (corpus.empty()) return usage("no seeds in " + (fs::path(o.corpus) / t->name).string());
    InputSequence sequence(o, *t, std::move(corpus));
    const long count = static_cast<long>(sequence.seeds()) + o.runs;
    if (o.input_index >= 0) {  // reproduce one input of a run
      for (long k = 0; k < o.input_index; ++k) sequence.input(k);
      std::cout << sequence.input(o.input_index);
      return 0;
    }
    Workspace w(t->companions ? aux : "");
    prepare_crash_path(finding_path(o, *t, "crash"));
    Stats st;
    for (long k = 0; k < count; ++k) run_one(o, *t, w, dog, sequence.input(k), k, st);
    total_findings += st.findings;
    std::cerr << "tb_fuzz: " << t->name << ": " << st.inputs << " inputs (" << sequence.seeds() << " seeds), "
              << st.accepted << " accepted, " << st.rejected << " rejected with " << st.kinds.size()
              << " distinct messages, " << st.findings << " findings; slowest " << std::fixed << std::setprecision(1)
              << st.slowest_ms << " ms (input " << st.slowest_index << "), total " << st.total_s << " s\n";
    nlohmann::json kinds = nlohmann::json::object();
    for (const auto& [k, n] : st.kind_count) kinds[k] = n;
    report[t->name] = {{"description", t->description},
                       {"inputs", st.inputs},
                       {"seeds", sequence.seeds()},
                       {"accepted", st.accepted},
                       {"rejected", st.rejected},
                       {"findings", st.findings},
                       {"crashes", 0},
                       {"hangs", 0},
                       {"distinct_messages", st.kinds.size()},
                       {"messages", kinds},
                       {"slowest_ms", st.slowest_ms},
                       {"slowest_input_index", st.slowest_index},
                       {"slowest_input_bytes", st.slowest_size},
                       {"slowest_outcome", st.slowest_outcome},
                       {"seconds", st.total_s},
                       {"seed", o.seed},
                       {"runs", o.runs}};
  }
  if (!o.report.empty())
    std::ofstream(o.report) << report.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) << "\n";
  if (!o.markdown.empty()) {
    std::ofstream md(o.markdown);
    md << "| target | reader | inputs | accepted | rejected | findings | crashes | hangs | distinct error messages | "
          "slowest input (ms) |\n|---|---|---|---|---|---|---|---|---|---|\n";
    for (const auto& [name, r] : report.items())
      md << "| " << name << " | " << r["description"].get<std::string>() << " | " << r["inputs"] << " | "
         << r["accepted"] << " | " << r["rejected"] << " | " << r["findings"] << " | 0 | 0 | " << r["distinct_messages"]
         << " | " << std::fixed << std::setprecision(1) << r["slowest_ms"].get<double>() << " |\n";
  }
  return total_findings ? 1 : 0;
}

}  // namespace
}  // namespace tb::fuzz

int main(int argc, char** argv) {
  try {
    return tb::fuzz::main_impl(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "tb_fuzz: " << e.what() << "\n";
    return 2;
  }
}
