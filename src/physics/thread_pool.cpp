#include "thread_pool.h"

namespace pg {

ThreadPool::ThreadPool(int threads) {
  for (int i = 1; i < threads; ++i) m_workers.emplace_back([this] { WorkerLoop(); });
}

ThreadPool::~ThreadPool() {
  {
    std::lock_guard<std::mutex> lock(m_mutex);
    m_stop = true;
  }
  m_wake.notify_all();
  for (std::thread& t : m_workers) t.join();
}

void ThreadPool::Run(int count, const std::function<void(int)>& job) {
  if (m_workers.empty() || count <= 1) {
    for (int i = 0; i < count; ++i) job(i);
    return;
  }
  // publish the batch, then work on it too
  {
    std::lock_guard<std::mutex> lock(m_mutex);
    m_job = &job;
    m_count = count;
    m_next = 0;
    m_finished = 0;
    ++m_generation;
  }
  m_wake.notify_all();
  Drain();
  std::unique_lock<std::mutex> lock(m_mutex);
  m_done.wait(lock, [this] { return m_finished == m_count; });
  m_job = nullptr;
}

void ThreadPool::Drain() {
  for (;;) {
    int i;
    const std::function<void(int)>* job;
    {
      std::lock_guard<std::mutex> lock(m_mutex);
      if (m_job == nullptr || m_next >= m_count) return;
      i = m_next++;
      job = m_job;
    }
    (*job)(i);
    bool last;
    {
      std::lock_guard<std::mutex> lock(m_mutex);
      last = ++m_finished == m_count;
    }
    if (last) m_done.notify_all();
  }
}

void ThreadPool::WorkerLoop() {
  uint64_t seen = 0;
  for (;;) {
    {
      std::unique_lock<std::mutex> lock(m_mutex);
      m_wake.wait(lock, [&] { return m_stop || m_generation != seen; });
      if (m_stop) return;
      seen = m_generation;
    }
    Drain();
  }
}

}  // namespace pg
