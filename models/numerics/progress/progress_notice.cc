// The per-thread sink of progress_notice.h.
#include "progress_notice.h"

#include <utility>

namespace tb {
namespace {
thread_local ProgressNoticeSink current_sink;
}

ScopedProgressNotices::ScopedProgressNotices(ProgressNoticeSink sink) : previous_(std::move(current_sink)) {
  current_sink = std::move(sink);
}

ScopedProgressNotices::~ScopedProgressNotices() { current_sink = std::move(previous_); }

bool progress_notices_wanted() { return static_cast<bool>(current_sink); }

void progress_notice(const std::string& text) noexcept {
  // A line that cannot be printed is dropped: it must not stop the solve it reports on.
  try {
    if (current_sink) current_sink(text);
  } catch (...) {
  }
}

bool ProgressNoticeClock::due() {
  if (!progress_notices_wanted()) return false;
  const auto now = std::chrono::steady_clock::now();
  if (now - last_ < period_) return false;
  last_ = now;
  return true;
}

}  // namespace tb
