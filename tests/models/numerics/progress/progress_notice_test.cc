// A model's progress lines (progress_notice.h): they reach the sink this thread
// installed, nobody else's, and stop when it goes.
#include "progress_notice.h"

#include <gtest/gtest.h>

#include <string>
#include <thread>
#include <vector>

namespace tb {
namespace {

TEST(ProgressNotice, ReachesTheSinkOfItsThreadWhileItIsInstalled) {
  std::vector<std::string> heard;
  progress_notice("before any sink");  // nobody listens: nothing happens
  EXPECT_FALSE(progress_notices_wanted());
  {
    const ScopedProgressNotices outer([&](const std::string& t) { heard.push_back("outer: " + t); });
    progress_notice("a");
    {
      const ScopedProgressNotices inner([&](const std::string& t) { heard.push_back("inner: " + t); });
      progress_notice("b");
      std::thread other([] {
        EXPECT_FALSE(progress_notices_wanted()) << "another thread has no sink";
        progress_notice("from another thread");
      });
      other.join();
    }
    progress_notice("c");  // the outer sink again
  }
  progress_notice("after");
  EXPECT_FALSE(progress_notices_wanted());
  EXPECT_EQ(heard, (std::vector<std::string>{"outer: a", "inner: b", "outer: c"}));
}

TEST(ProgressNotice, TheClockIsDueOncePerPeriodAndOnlyWhenSomebodyListens) {
  ProgressNoticeClock every_time(std::chrono::seconds(0)), hourly(std::chrono::hours(1));
  EXPECT_FALSE(every_time.due()) << "no sink";
  const ScopedProgressNotices sink([](const std::string&) {});
  EXPECT_TRUE(every_time.due());
  EXPECT_TRUE(every_time.due());
  EXPECT_FALSE(hourly.due()) << "an hour has not passed since construction";
}

}  // namespace
}  // namespace tb
