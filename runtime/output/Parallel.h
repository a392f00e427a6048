// Runs a function over the indices 0..count-1 on a few threads: the image writers' bands.
#pragma once

#include <functional>

namespace moire {

// Calls fn(i) once for every i in [0, count), on `threads` threads (0: one per hardware
// thread; never more than count), the calling thread among them, each taking the next index
// as it finishes one. When a call throws, no further index is started and the first
// exception is rethrown once every thread has stopped.
void forEachInParallel(int count, int threads, const std::function<void(int)>& fn);

} // namespace moire
