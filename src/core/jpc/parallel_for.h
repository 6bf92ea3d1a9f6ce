#pragma once
// A minimal parallel loop for independent tasks that each write their own result slot,
// so results never depend on the thread count or on scheduling.

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace mlod {

// Calls task(i) for every i in [0, count), on up to `threads` threads (0 = one per
// hardware thread). The first exception a task throws is rethrown here after every
// thread has stopped.
template <typename Task> void parallelFor(int count, int threads, Task&& task) {
  if (count <= 0)
    return;
  if (threads <= 0)
    threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  threads = std::min(threads, count);
  if (threads == 1) {
    for (int i = 0; i < count; ++i)
      task(i);
    return;
  }
  std::atomic<int> next{0};
  std::exception_ptr failure;
  std::mutex failureMutex;
  const auto worker = [&] {
    for (int i = next.fetch_add(1); i < count; i = next.fetch_add(1)) {
      try {
        task(i);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(failureMutex);
        if (!failure)
          failure = std::current_exception();
        next.store(count);
      }
    }
  };
  std::vector<std::thread> pool;
  pool.reserve(static_cast<std::size_t>(threads - 1));
  for (int t = 1; t < threads; ++t)
    pool.emplace_back(worker);
  worker();
  for (std::thread& thread : pool)
    thread.join();
  if (failure)
    std::rethrow_exception(failure);
}

} // namespace mlod
