// qrm/support.hpp: what every layer may use: seeded random numbers and parallel jobs.
//   support/random.hpp     seeded, platform-independent generator; binomial sampling
//   support/parallel.hpp   run jobs on threads (results independent of the thread count)
// Internals: support/detail/meta.hpp (type lists, fixed strings), support/detail/thread_pool.hpp.
#pragma once

#include "support/parallel.hpp"
#include "support/random.hpp"
