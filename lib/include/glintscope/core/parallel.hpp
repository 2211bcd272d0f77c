#pragma once
// The heavy loops run on a fixed set of threads. Work is split into chunks whose boundaries
// depend only on the problem size, never on the thread count, and reductions combine chunk
// results in chunk order, so every result is bit-identical for any thread count.
#include <cstddef>
#include <functional>

namespace glintscope {

// Threads are the caller's: there is no process-wide setting. parallel_for uses the count of the
// innermost ThreadScope alive on the calling thread (the workers it starts inherit it), else
// $GLINTSCOPE_THREADS or the hardware concurrency, so calls made from different threads never
// change each other's count.
int thread_count();

// The thread count of the library calls the constructing thread makes until the scope ends
// (0: the default); scopes nest. A renderer's threads calling Bsdf::eval/sample need none:
// those start no threads.
class ThreadScope {
public:
    explicit ThreadScope(int threads);
    ~ThreadScope();
    ThreadScope(const ThreadScope&) = delete;
    ThreadScope& operator=(const ThreadScope&) = delete;

private:
    int previous_;
};

// body() run inside a ThreadScope of `threads`, returning what it returns.
template <typename Body>
auto with_threads(int threads, const Body& body) {
    const ThreadScope scope(threads);
    return body();
}

// Progress of a long call made while the scope lives on the constructing thread: every
// parallel_for that thread starts (not those nested in a loop's body) counts its chunks as they
// finish, and report(fraction) is called with the chunks done over the chunks of all the loops
// started so far, rounded down to thousandths and only when that rises (so never decreasing,
// and below 1 until finish() reports 1). Calls are serialised (from any of the loop's threads).
class ProgressScope {
public:
    explicit ProgressScope(std::function<void(double fraction)> report);
    ~ProgressScope();
    ProgressScope(const ProgressScope&) = delete;
    ProgressScope& operator=(const ProgressScope&) = delete;

    void finish();  // reports 1, once

    struct State;  // the counts, shared with the loops

private:
    State* state_;
    State* previous_;
};

// Calls body(begin, end) for consecutive chunks [begin, end) of [0, count) of at most
// `chunk` items each, spread over the threads. Exceptions thrown by a body are rethrown.
void parallel_for(std::size_t count, std::size_t chunk,
                  const std::function<void(std::size_t begin, std::size_t end)>& body);

}  // namespace glintscope
