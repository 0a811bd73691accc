// qrm/support/detail/thread_pool.hpp: a persistent pool of std::threads for the dense kernels.
//
// Starting threads per gate costs far more than a small gate, so workers are created once and
// wait on a condition variable. Work is split into chunks whose boundaries do not depend on the
// thread count, so results (including reductions summed per chunk) are bit-identical for any
// number of threads. If the pool is busy (another thread is running a job) the caller runs the
// job itself instead of waiting.
#pragma once

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <mutex>
#include <thread>
#include <vector>

namespace qrm::detail {

// chunk_job: a non-owning reference to a callable taking a chunk index. Unlike std::function it
// instantiates one small trampoline per kernel and never allocates.
class chunk_job {
 public:
  template <class F>
  chunk_job(const F& f) : object_(&f), call_([](const void* o, std::size_t i) { (*static_cast<const F*>(o))(i); }) {}
  void operator()(std::size_t i) const { call_(object_, i); }

 private:
  const void* object_;
  void (*call_)(const void*, std::size_t);
};

template <int = 0>
class thread_pool {
 public:
  explicit thread_pool(unsigned threads) {
    const unsigned workers = threads > 1 ? threads - 1 : 0;
    for (unsigned i = 0; i < workers; ++i) workers_.emplace_back([this] { work(); });
  }
  thread_pool(const thread_pool&) = delete;
  thread_pool& operator=(const thread_pool&) = delete;
  ~thread_pool() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    for (auto& t : workers_) t.join();
  }

  unsigned size() const { return static_cast<unsigned>(workers_.size()) + 1; }

  // Calls fn(i) for i in [0, chunks), spread over at most `threads` threads (caller included).
  void parallel_for(std::size_t chunks, unsigned threads, chunk_job fn) {
    if (chunks == 0) return;
    std::unique_lock<std::mutex> job(job_mutex_, std::try_to_lock);
    const unsigned helpers = std::min<unsigned>(threads > 0 ? threads - 1 : 0, static_cast<unsigned>(workers_.size()));
    if (!job.owns_lock() || helpers == 0 || chunks == 1) {
      for (std::size_t i = 0; i < chunks; ++i) fn(i);
      return;
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      fn_ = &fn;
      chunks_ = chunks;
      next_.store(0);
      active_helpers_ = helpers;
      pending_helpers_ = helpers;
      ++generation_;
    }
    wake_.notify_all();
    drain();
    std::unique_lock<std::mutex> lock(mutex_);
    done_.wait(lock, [this] { return pending_helpers_ == 0; });
    fn_ = nullptr;
  }

 private:
  void drain() {
    for (;;) {
      const std::size_t i = next_.fetch_add(1);
      if (i >= chunks_) return;
      (*fn_)(i);
    }
  }
  void work() {
    std::size_t seen = 0;
    for (;;) {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [&] { return stop_ || (generation_ != seen && active_helpers_ > 0); });
      if (stop_) return;
      seen = generation_;
      --active_helpers_;
      lock.unlock();
      drain();
      lock.lock();
      if (--pending_helpers_ == 0) done_.notify_one();
    }
  }

  std::vector<std::thread> workers_;
  std::mutex mutex_, job_mutex_;
  std::condition_variable wake_, done_;
  const chunk_job* fn_ = nullptr;
  std::size_t chunks_ = 0;
  std::atomic<std::size_t> next_{0};
  unsigned active_helpers_ = 0, pending_helpers_ = 0;
  std::size_t generation_ = 0;
  bool stop_ = false;
};

// The process-wide pool, sized to the hardware on first use.
template <int Deferred = 0>
inline thread_pool<Deferred>& shared_pool() {
  static thread_pool<Deferred> pool(std::max(1u, std::thread::hardware_concurrency()));
  return pool;
}

}  // namespace qrm::detail
