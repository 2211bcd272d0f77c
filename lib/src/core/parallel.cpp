#include "glintscope/core/parallel.hpp"

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <exception>
#include <mutex>
#include <system_error>
#include <thread>
#include <vector>

namespace glintscope {
namespace {

// The calling thread's ThreadScope count; 0: none.
thread_local int scoped_threads = 0;

// The calling thread's ProgressScope, and whether it is inside a parallel_for (whose nested
// loops do not count).
thread_local ProgressScope::State* scoped_progress = nullptr;
thread_local bool inside_loop = false;

// Read once: parallel_for is called from small inner loops too.
int default_thread_count() {
    static const int threads = [] {
        if (const char* env = std::getenv("GLINTSCOPE_THREADS")) {
            const int n = std::atoi(env);
            if (n > 0) return n;
        }
        return static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    }();
    return threads;
}

}  // namespace

struct ProgressScope::State {
    Report report;
    std::mutex mutex;
    std::size_t pass = 0;
    std::size_t done = 0;   // chunks of this pass
    std::size_t total = 0;
    std::size_t reported_thousandths = 0;

    void started(std::size_t chunks) {
        std::lock_guard lock(mutex);
        ++pass;
        done = 0;
        total = chunks;
        reported_thousandths = 0;
    }
    void chunk_done() {
        std::lock_guard lock(mutex);
        ++done;
        const std::size_t thousandths = 1000 * done / total;
        if (thousandths <= reported_thousandths && done < total) return;
        reported_thousandths = thousandths;
        report(pass, done, total);
    }
};

ProgressScope::ProgressScope(Report report) : state_(new State{std::move(report), {}, 0, 0, 0, 0}), previous_(scoped_progress) {
    scoped_progress = state_;
}

ProgressScope::~ProgressScope() {
    scoped_progress = previous_;
    delete state_;
}

int thread_count() { return scoped_threads > 0 ? scoped_threads : default_thread_count(); }

ThreadScope::ThreadScope(int threads) : previous_(scoped_threads) { scoped_threads = std::max(0, threads); }

ThreadScope::~ThreadScope() { scoped_threads = previous_; }

namespace {

// Runs the loop with the chunks counted by the calling thread's ProgressScope, if any.
void run_loop(std::size_t count, std::size_t chunk, const std::function<void(std::size_t, std::size_t)>& body);

}  // namespace

void parallel_for(std::size_t count, std::size_t chunk,
                  const std::function<void(std::size_t, std::size_t)>& body) {
    if (count == 0) return;
    chunk = std::max<std::size_t>(1, chunk);
    ProgressScope::State* progress = inside_loop ? nullptr : scoped_progress;
    if (!progress) return run_loop(count, chunk, body);
    progress->started((count + chunk - 1) / chunk);
    struct InsideLoop {  // for the loop's duration, even when it throws
        InsideLoop() { inside_loop = true; }
        ~InsideLoop() { inside_loop = false; }
    } inside;
    run_loop(count, chunk, [&](std::size_t begin, std::size_t end) {
        body(begin, end);
        progress->chunk_done();
    });
}

namespace {

void run_loop(std::size_t count, std::size_t chunk, const std::function<void(std::size_t, std::size_t)>& body) {
    const std::size_t chunks = (count + chunk - 1) / chunk;
    const int threads = thread_count();
    const std::size_t workers = std::min<std::size_t>(static_cast<std::size_t>(threads), chunks);
    if (workers <= 1) {
        for (std::size_t begin = 0; begin < count; begin += chunk) body(begin, std::min(count, begin + chunk));
        return;
    }
    std::atomic<std::size_t> next{0};
    std::exception_ptr failure;
    std::mutex failure_mutex;
    const auto work = [&] {
        for (;;) {
            const std::size_t index = next.fetch_add(1);
            if (index >= chunks) return;
            const std::size_t begin = index * chunk;
            try {
                body(begin, std::min(count, begin + chunk));
            } catch (...) {
                std::lock_guard lock(failure_mutex);
                if (!failure) failure = std::current_exception();
                next.store(chunks);
            }
        }
    };
    std::vector<std::thread> pool;
    pool.reserve(workers - 1);
    // A thread the system refuses (process or memory limits) is not needed: the threads started
    // share the chunks, and the calling thread alone would finish them all. Chunks do not depend
    // on the thread count, so neither does the result.
    try {
        for (std::size_t t = 1; t < workers; ++t)
            pool.emplace_back([&] {
                const ThreadScope inherited(threads);  // for loops nested in the body
                work();
            });
    } catch (const std::exception&) {  // std::system_error, or std::bad_alloc for the thread's state
    }
    work();
    for (auto& thread : pool) thread.join();
    if (failure) std::rethrow_exception(failure);
}

}  // namespace

}  // namespace glintscope
