#pragma once
// A fixed set of worker threads that the runtime's jobs spread characters over. The
// caller owns it (as it owns every buffer) and keeps it for the life of the crowd:
// threads start once, in the constructor, and run() neither allocates nor starts
// threads, so a job can run on it every frame.
//
// Work is handed out in chunks from an atomic counter; which thread takes which chunk
// varies from run to run, so a task must give the same result on any thread (the jobs
// of the runtime write each character's output from that character's input alone).

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>
#include <vector>

namespace mlod {

class WorkerPool {
public:
  // A task: handles items [begin, end) on thread `thread` (0 = the caller of run()).
  using Task = void (*)(void* data, int begin, int end, int thread);

  // `threads` >= 1 in all, the calling thread included: 1 starts no thread.
  explicit WorkerPool(int threads = 1);
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  int threadCount() const { return static_cast<int>(m_workers.size()) + 1; }

  // Calls task(data, begin, end, thread) over [0, count) in chunks of `grain` items (>= 1)
  // on every thread, the caller's included, and returns when all are done. One run at a
  // time: run() is not reentrant and must not be called from inside a task.
  void run(int count, int grain, Task task, void* data);

private:
  void work(int thread);
  void drain(int thread);

  std::vector<std::thread> m_workers;
  std::mutex m_mutex;
  std::condition_variable m_wake;
  std::condition_variable m_done;
  std::uint64_t m_generation = 0; // incremented per run; workers wait for a new one
  int m_busy = 0;                 // workers still inside the current run
  bool m_stop = false;
  // the current run
  Task m_task = nullptr;
  void* m_data = nullptr;
  int m_count = 0;
  int m_grain = 1;
  std::atomic<int> m_next{0};
};

} // namespace mlod
