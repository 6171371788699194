// A small fixed pool of threads that runs a batch of independent jobs and waits for all of them.
// Jobs are claimed in index order from a shared counter; each job runs entirely on one thread, so
// jobs that touch disjoint data give the same results however they are spread over threads.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace pg {

/// Runs batches of jobs on threads - 1 workers plus the calling thread.
class ThreadPool {
 public:
  /// threads <= 1 runs every job on the caller.
  explicit ThreadPool(int threads);
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  /// Calls job(i) for i in [0, count) and returns when all have finished.
  void Run(int count, const std::function<void(int)>& job);

  /// Threads that run jobs, the caller included.
  int Threads() const { return static_cast<int>(m_workers.size()) + 1; }

 private:
  void WorkerLoop();
  void Drain();

  std::vector<std::thread> m_workers;
  std::mutex m_mutex;
  std::condition_variable m_wake;
  std::condition_variable m_done;
  const std::function<void(int)>* m_job = nullptr;
  int m_count = 0;
  int m_next = 0;
  int m_finished = 0;
  uint64_t m_generation = 0;
  bool m_stop = false;
};

}  // namespace pg
