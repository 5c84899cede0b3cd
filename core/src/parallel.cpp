// SPDX-License-Identifier: MIT
#include "deepcut/core/parallel.h"

#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>

#include "deepcut/core/process_memory.h"
#include "uninit_vector.h"

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
// Workers sleep on a condition variable between jobs (the machine may be shared: no spinning).
// The caller waits for the chunks, never for a worker to wake up: a worker the scheduler runs
// late finds every chunk taken and goes back to sleep, so a busy machine costs no more than
// running serially.
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
    auto job = std::make_shared<Job>();
    job->task = &task;
    job->chunks = chunks;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      job_ = job;
      ++generation_;
    }
    wake_.notify_all();
    t_inside = true;
    job->work();
    t_inside = false;
    if (job->done.load(std::memory_order_acquire) != chunks) {  // a worker still runs one
      std::unique_lock<std::mutex> lock(job->mutex);
      job->finished.wait(lock, [&] { return job->done.load(std::memory_order_acquire) == chunks; });
    }
    if (job->error) std::rethrow_exception(job->error);
  }

 private:
  struct Job {
    const std::function<void(std::size_t)>* task = nullptr;
    std::size_t chunks = 0;
    std::atomic<std::size_t> next{0};
    // Chunks finished: each thread adds its own once, when it finds none left, so the mutex is
    // taken only by a failed chunk and by the thread that finishes the job (to wake the caller
    // if it waits), not once per chunk.
    std::atomic<std::size_t> done{0};
    std::mutex mutex;  // guards error; the caller waits on `finished` under it
    std::condition_variable finished;
    std::exception_ptr error;

    // Takes chunks until none are left.
    void work() {
      std::size_t ran = 0;
      for (;; ++ran) {
        const std::size_t c = next.fetch_add(1, std::memory_order_relaxed);
        if (c >= chunks) break;
        try {
          (*task)(c);
        } catch (...) {
          std::lock_guard<std::mutex> lock(mutex);
          if (!error) error = std::current_exception();
        }
      }
      // Release: the chunks' writes are seen by the caller that reads `done` (acquire).
      if (ran == 0 || done.fetch_add(ran, std::memory_order_acq_rel) + ran != chunks) return;
      std::lock_guard<std::mutex> lock(mutex);  // the caller is waiting or has not checked yet
      finished.notify_all();
    }
  };

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

  void worker_loop() {
    t_inside = true;
    std::uint64_t seen = 0;
    for (;;) {
      std::shared_ptr<Job> job;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        wake_.wait(lock, [&] { return quit_ || generation_ != seen; });
        if (quit_) return;
        seen = generation_;
        job = job_;
      }
      if (job) job->work();
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
      job_.reset();
    }
    wake_.notify_all();
    for (auto& w : workers_) w.join();
    workers_.clear();
  }

  std::mutex submit_;  // one job at a time
  std::mutex mutex_;   // guards job_, generation_ and quit_
  std::condition_variable wake_;
  std::vector<std::thread> workers_;
  std::shared_ptr<Job> job_;
  std::uint64_t generation_ = 0;
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

namespace detail {

void prefault(void* data, std::size_t bytes) {
#ifdef MADV_POPULATE_WRITE
  constexpr std::size_t kPart = std::size_t(2) << 20;
  const PageSpan pages = inner_pages(data, static_cast<char*>(data) + bytes);
  if (pages.last - pages.first < kPart) return;  // a few pages: faulting them costs less
  parallel_for(pages.last - pages.first, kPart, [&](std::size_t b, std::size_t e) {
    // A refusal only costs speed.
    ::madvise(reinterpret_cast<void*>(pages.first + b), e - b, MADV_POPULATE_WRITE);
  });
#else
  (void)data;
  (void)bytes;
#endif
}

}  // namespace detail
}  // namespace deepcut
