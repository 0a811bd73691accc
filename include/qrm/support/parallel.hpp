// qrm/support/parallel.hpp: independent jobs over std::threads (cells of a light map, pixels),
// handed out one at a time; the first exception thrown by any job stops the others and is
// rethrown to the caller (an exception escaping a std::thread would terminate the program).
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace qrm::detail {

// parallel_jobs(count, threads, job): job(i) for every i < count; threads = 0 means all cores.
// Results must be written per job (job i owns its output), so they do not depend on threads.
template <class Job>
void parallel_jobs(std::size_t count, unsigned threads, Job&& job) {
  std::atomic<std::size_t> next{0};
  std::exception_ptr failure;
  std::mutex failure_mutex;
  auto work = [&] {
    try {
      for (std::size_t i; (i = next.fetch_add(1)) < count;) job(i);
    } catch (...) {
      std::lock_guard<std::mutex> lock(failure_mutex);
      if (!failure) failure = std::current_exception();
      next = count;
    }
  };
  const unsigned n = threads ? threads : std::max(1u, std::thread::hardware_concurrency());
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < n && t < count; ++t) pool.emplace_back(work);
  work();
  for (auto& t : pool) t.join();
  if (failure) std::rethrow_exception(failure);
}

}  // namespace qrm::detail
