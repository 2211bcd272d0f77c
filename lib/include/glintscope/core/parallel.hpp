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

// Progress of a long call made while the scope lives on the constructing thread, pass by pass:
// every parallel_for that thread starts (not those nested in a loop's body) is a pass, numbered
// from 1, and report(pass, done, total) is called as its chunks finish: done of its total
// chunks, rising, whenever a thousandth more is done and at the last chunk. Calls are serialised
// (they come from any of the loop's threads). The passes are reported as they come: the scope
// cannot know how many more a method will start.
class ProgressScope {
public:
    using Report = std::function<void(std::size_t pass, std::size_t done, std::size_t total)>;
    explicit ProgressScope(Report report);
    ~ProgressScope();
    ProgressScope(const ProgressScope&) = delete;
    ProgressScope& operator=(const ProgressScope&) = delete;

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
