// SPDX-License-Identifier: MIT
#include "deepcut/core/parallel.h"

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstdlib>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>

#include <unistd.h>

namespace deepcut {
namespace {

// True on pool workers and on a caller while it runs chunks: nested calls run inline.
thread_local bool t_inside = false;

std::size_t default_threads() {
  if (const char* env = std::getenv("DEEPCUT_THREADS")) {
    char* end = nullptr;
    const long n = std::strtol(env, &end, 10);
    if (end != env && *end == '\0' && n > 0) return static_cast<std::size_t>(std::min(n, 256L));
  }
  const unsigned hw = std::thread::hardware_concurrency();
  return hw == 0 ? 1 : hw;
}

// One job at a time: the caller publishes it, wakes the workers, and takes chunks itself.
// Workers sleep on a condition variable between jobs (the machine is shared: no spinning).
class Pool {
 public:
  explicit Pool(std::size_t threads) { start(threads); }
  ~Pool() { stop(); }

  std::size_t size() const { return workers_.size() + 1; }

  void resize(std::size_t threads) {
    std::lock_guard<std::mutex> submit(submit_);
    stop();
    start(threads);
  }

  void run(std::size_t chunks, const std::function<void(std::size_t)>& task) {
    std::unique_lock<std::mutex> submit(submit_, std::try_to_lock);
    // Serial when nested, when the pool is busy with another caller's job, when alone, or in a
    // forked child (which has none of the parent's worker threads).
    if (t_inside || !submit.owns_lock() || workers_.empty() || chunks == 1 || getpid() != owner_) {
      run_serial(chunks, task);
      return;
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      task_ = &task;
      chunks_ = chunks;
      next_.store(0, std::memory_order_relaxed);
      pending_ = workers_.size();
      error_ = nullptr;
      ++generation_;
    }
    wake_.notify_all();
    t_inside = true;
    work();
    t_inside = false;
    std::unique_lock<std::mutex> lock(mutex_);
    done_.wait(lock, [&] { return pending_ == 0; });
    task_ = nullptr;
    if (error_) std::rethrow_exception(error_);
  }

 private:
  static void run_serial(std::size_t chunks, const std::function<void(std::size_t)>& task) {
    const bool was_inside = t_inside;
    t_inside = true;
    std::exception_ptr error;
    for (std::size_t c = 0; c < chunks; ++c) {
      try {
        task(c);
      } catch (...) {
        if (!error) error = std::current_exception();
      }
    }
    t_inside = was_inside;
    if (error) std::rethrow_exception(error);
  }

  // Takes chunks until none are left.
  void work() {
    for (;;) {
      const std::size_t c = next_.fetch_add(1, std::memory_order_relaxed);
      if (c >= chunks_) return;
      try {
        (*task_)(c);
      } catch (...) {
        std::lock_guard<std::mutex> lock(mutex_);
        if (!error_) error_ = std::current_exception();
      }
    }
  }

  void worker_loop() {
    t_inside = true;
    std::uint64_t seen = 0;
    for (;;) {
      {
        std::unique_lock<std::mutex> lock(mutex_);
        wake_.wait(lock, [&] { return quit_ || generation_ != seen; });
        if (quit_) return;
        seen = generation_;
      }
      work();
      std::lock_guard<std::mutex> lock(mutex_);
      if (--pending_ == 0) done_.notify_one();
    }
  }

  void start(std::size_t threads) {
    quit_ = false;
    owner_ = getpid();
    for (std::size_t i = 1; i < std::max<std::size_t>(threads, 1); ++i) workers_.emplace_back([this] { worker_loop(); });
  }

  void stop() {
    if (getpid() != owner_) {
      // A forked child: the workers are the parent's; their handles can be neither joined nor
      // destroyed here, so they are left alone.
      static_cast<void>(new std::vector<std::thread>(std::move(workers_)));
      workers_.clear();
      return;
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      quit_ = true;
    }
    wake_.notify_all();
    for (auto& w : workers_) w.join();
    workers_.clear();
  }

  std::mutex submit_;  // one job at a time
  std::mutex mutex_;   // guards the job fields below
  std::condition_variable wake_, done_;
  std::vector<std::thread> workers_;
  const std::function<void(std::size_t)>* task_ = nullptr;
  std::size_t chunks_ = 0;
  std::atomic<std::size_t> next_{0};
  std::size_t pending_ = 0;
  std::uint64_t generation_ = 0;
  std::exception_ptr error_;
  bool quit_ = false;
  pid_t owner_ = 0;
};

Pool& pool() {
  static Pool instance(default_threads());
  return instance;
}

}  // namespace

std::size_t thread_count() { return pool().size(); }

void set_thread_count(std::size_t threads) { pool().resize(std::max<std::size_t>(threads, 1)); }

namespace detail {
void run_chunks(std::size_t chunks, const std::function<void(std::size_t)>& task) {
  if (chunks == 0) return;
  pool().run(chunks, task);
}
}  // namespace detail

void parallel_invoke(const std::vector<std::function<void()>>& tasks) {
  detail::run_chunks(tasks.size(), [&](std::size_t i) { tasks[i](); });
}

}  // namespace deepcut
