// ThreadPool (src/physics/thread_pool.cpp): every job of every batch runs exactly once.
#include "thread_pool.h"

#include <gtest/gtest.h>

#include <atomic>
#include <vector>

namespace pg {
namespace {

TEST(ThreadPool, RunsEveryJobOnceInEveryBatch) {
  for (int threads = 1; threads <= 4; ++threads) {
    ThreadPool pool(threads);
    EXPECT_EQ(pool.Threads(), threads);
    for (int batch = 0; batch < 200; ++batch) {
      const int count = 1 + batch % 17;
      std::vector<std::atomic<int>> hits(count);
      pool.Run(count, [&](int i) { hits[i].fetch_add(1); });
      for (int i = 0; i < count; ++i) ASSERT_EQ(hits[i].load(), 1) << threads << " threads";
    }
  }
}

TEST(ThreadPool, EmptyBatchReturns) {
  ThreadPool pool(3);
  int calls = 0;
  pool.Run(0, [&](int) { ++calls; });
  EXPECT_EQ(calls, 0);
}

}  // namespace
}  // namespace pg
