// A long computation's word to whoever runs it: a line of progress from inside a
// model's frame (a Newton solve that takes minutes on a large mesh, a continuation
// past a fold), which the runner prints among its own progress lines on stderr. By
// default nobody listens and a notice costs a test of one pointer.
//
// The sink is per thread: the runner runs a case's frames on the thread that
// installs it, and a thread team's workers, which never notice, cannot race on it.
#pragma once

#include <chrono>
#include <functional>
#include <string>

namespace tb {

using ProgressNoticeSink = std::function<void(const std::string&)>;

/// Installs `sink` for this thread for its lifetime (the previous one after).
class ScopedProgressNotices {
 public:
  explicit ScopedProgressNotices(ProgressNoticeSink sink);
  ~ScopedProgressNotices();
  ScopedProgressNotices(const ScopedProgressNotices&) = delete;
  ScopedProgressNotices& operator=(const ScopedProgressNotices&) = delete;

 private:
  ProgressNoticeSink previous_;
};

/// True when a sink listens on this thread (a caller may skip composing the text).
bool progress_notices_wanted();

/// Hands `text` (one line, no newline) to this thread's sink, if any; a sink that
/// throws loses the line, not the caller's work.
void progress_notice(const std::string& text) noexcept;

/// At most one notice a period: due() is true once `period` has passed since the
/// last time it was (or since construction), and only when a sink listens.
class ProgressNoticeClock {
 public:
  explicit ProgressNoticeClock(std::chrono::steady_clock::duration period) : period_(period) { restart(); }
  void restart() { last_ = std::chrono::steady_clock::now(); }
  bool due();

 private:
  std::chrono::steady_clock::duration period_;
  std::chrono::steady_clock::time_point last_;
};

}  // namespace tb
