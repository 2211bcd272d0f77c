#pragma once
// The heavy loops run on a fixed set of threads. Work is split into chunks whose boundaries
// depend only on the problem size, never on the thread count, and reductions combine chunk
// results in chunk order, so every result is bit-identical for any thread count.
#include <cstddef>
#include <functional>

namespace glintscope {

// Threads used by parallel_for; defaults to $GLINTSCOPE_THREADS or the hardware concurrency.
int thread_count();
void set_thread_count(int threads);  // 0 restores the default

// Calls body(begin, end) for consecutive chunks [begin, end) of [0, count) of at most
// `chunk` items each, spread over the threads. Exceptions thrown by a body are rethrown.
void parallel_for(std::size_t count, std::size_t chunk,
                  const std::function<void(std::size_t begin, std::size_t end)>& body);

// The same on `threads` threads (0: thread_count()), for callers that take a thread count per call.
void parallel_for(std::size_t count, std::size_t chunk, int threads,
                  const std::function<void(std::size_t begin, std::size_t end)>& body);

}  // namespace glintscope
