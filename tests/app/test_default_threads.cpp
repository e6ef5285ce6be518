// The default thread count on a shared machine (issue 35, point 6; src/app/default_threads.hpp): one thread per
// core that the load average says is free, at least one; an idle machine keeps every core.
#include <gtest/gtest.h>

#include "app/default_threads.hpp"

using varsph::threads_for_load;

TEST(DefaultThreads, OnePerFreeCoreAtLeastOne) {
  EXPECT_EQ(threads_for_load(2, 0.0), 2);   // idle: both cores (docs/performance.md: 1.7-2.3x faster)
  EXPECT_EQ(threads_for_load(2, 0.97), 2);  // a job winding down: not yet a whole busy core
  EXPECT_EQ(threads_for_load(2, 1.1), 1);   // one other job: the second thread would wait on its core
  EXPECT_EQ(threads_for_load(2, 8.4), 1);   // the build machine while others compile (README)
  EXPECT_EQ(threads_for_load(16, 3.5), 13);
  EXPECT_EQ(threads_for_load(4, -1), 4);    // no load average (not Linux): every core, as before
  EXPECT_GE(varsph::load_average(), 0.0);   // Linux: /proc/loadavg is read
}
