#include "util/parallel.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

#include "util/error.h"

namespace subsplat {

void parallelFor(size_t count, size_t chunk, const std::function<void(size_t, size_t)>& body,
                 const ProgressFunction& progress, double base, double span) {
  chunk = std::max<size_t>(chunk, 1);
  std::atomic<size_t> next{0}, done{0};
  std::atomic<bool> stop{false};
  std::exception_ptr error;
  std::mutex mutex;
  std::condition_variable finished;
  unsigned workers = std::max(1u, std::thread::hardware_concurrency());
  unsigned running = workers;

  auto work = [&] {
    try {
      for (;;) {
        if (stop.load(std::memory_order_relaxed)) break;
        size_t begin = next.fetch_add(chunk);
        if (begin >= count) break;
        size_t end = std::min(count, begin + chunk);
        body(begin, end);
        done.fetch_add(end - begin);
      }
    } catch (...) {
      std::lock_guard<std::mutex> lock(mutex);
      if (!error) error = std::current_exception();
      stop = true;
    }
    std::lock_guard<std::mutex> lock(mutex);
    if (--running == 0) finished.notify_all();
  };

  std::vector<std::thread> threads;
  threads.reserve(workers);
  try {
    for (unsigned i = 0; i < workers; ++i) threads.emplace_back(work);
  } catch (...) {
    // Could not start every thread: the ones that started finish the work.
    std::lock_guard<std::mutex> lock(mutex);
    running -= workers - unsigned(threads.size());
    if (threads.empty()) fail(SS_OUT_OF_MEMORY, "could not start worker threads");
  }

  bool cancelled = false;
  {
    std::unique_lock<std::mutex> lock(mutex);
    while (running > 0) {
      finished.wait_for(lock, std::chrono::milliseconds(100));
      if (running == 0 || !progress || cancelled) continue;
      lock.unlock();
      bool go = false;
      try {
        go = progress(base + span * double(done.load()) / double(std::max<size_t>(count, 1)));
      } catch (...) {  // stop the workers before anything leaves this function
        lock.lock();
        if (!error) error = std::current_exception();
        lock.unlock();
      }
      lock.lock();
      if (!go) {
        cancelled = true;
        stop = true;
      }
    }
  }
  for (std::thread& t : threads) t.join();
  if (error) std::rethrow_exception(error);
  if (cancelled) fail(SS_CANCELLED, "cancelled");
  if (progress && !progress(base + span)) fail(SS_CANCELLED, "cancelled");
}

}  // namespace subsplat
