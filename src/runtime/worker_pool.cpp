#include "runtime/worker_pool.h"

#include <algorithm>
#include <cassert>

namespace mlod {

WorkerPool::WorkerPool(int threads) {
  assert(threads >= 1);
  const int workers = std::max(threads, 1) - 1;
  m_workers.reserve(static_cast<std::size_t>(workers));
  for (int i = 0; i < workers; ++i)
    m_workers.emplace_back([this, i] { work(i + 1); });
}

WorkerPool::~WorkerPool() {
  {
    std::lock_guard<std::mutex> lock(m_mutex);
    m_stop = true;
  }
  m_wake.notify_all();
  for (std::thread& worker : m_workers)
    worker.join();
}

void WorkerPool::drain(int thread) {
  for (;;) {
    const int begin = m_next.fetch_add(m_grain, std::memory_order_relaxed);
    if (begin >= m_count)
      return;
    m_task(m_data, begin, std::min(begin + m_grain, m_count), thread);
  }
}

void WorkerPool::work(int thread) {
  std::uint64_t seen = 0;
  for (;;) {
    {
      std::unique_lock<std::mutex> lock(m_mutex);
      m_wake.wait(lock, [&] { return m_stop || m_generation != seen; });
      if (m_stop)
        return;
      seen = m_generation;
    }
    drain(thread);
    {
      std::lock_guard<std::mutex> lock(m_mutex);
      if (--m_busy == 0)
        m_done.notify_one();
    }
  }
}

void WorkerPool::run(int count, int grain, Task task, void* data) {
  assert(task && grain >= 1);
  if (count <= 0)
    return;
  if (m_workers.empty() || count <= grain) {
    task(data, 0, count, 0);
    return;
  }
  {
    std::lock_guard<std::mutex> lock(m_mutex);
    m_task = task;
    m_data = data;
    m_count = count;
    m_grain = std::max(grain, 1);
    m_next.store(0, std::memory_order_relaxed);
    m_busy = static_cast<int>(m_workers.size());
    ++m_generation;
  }
  m_wake.notify_all();
  drain(0);
  std::unique_lock<std::mutex> lock(m_mutex);
  m_done.wait(lock, [&] { return m_busy == 0; });
}

} // namespace mlod
