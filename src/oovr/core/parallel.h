// A minimal parallel-for. Work items are independent and write only their own
// outputs, so results never depend on the thread count or on scheduling.
#pragma once

#include <cstddef>
#include <functional>

namespace oovr {

// Number of worker threads to use when the caller asks for 0 ("automatic").
unsigned default_thread_count();

// Calls fn(i) for every i in [0, n) on up to `threads` threads (0 = automatic).
// Items are handed out dynamically; fn must only write state owned by item i.
// The first exception thrown by fn is rethrown on the calling thread.
void parallel_for(size_t n, unsigned threads, const std::function<void(size_t)>& fn);

}  // namespace oovr
