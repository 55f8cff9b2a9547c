#include "base/parallel.h"

#include <pthread.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <mutex>
#include <stdexcept>
#include <system_error>
#include <thread>
#include <vector>

namespace raycast {

int hardware_threads() { return std::max(1u, std::thread::hardware_concurrency()); }

namespace {

// The items of one parallel_for call, shared by the threads that work on it.
struct Job {
    const std::function<void(size_t, int)>* work = nullptr;
    size_t count = 0;
    std::atomic<size_t> next{0};
    std::atomic<bool> failed{false};
    std::exception_ptr first_error;
    std::mutex error_mutex;

    // Claims items one at a time until none is left or one has failed.
    void run(int worker) {
        for (;;) {
            const size_t item = next.fetch_add(1);
            if (item >= count || failed.load()) return;
            try {
                (*work)(item, worker);
            } catch (...) {
                std::lock_guard<std::mutex> lock(error_mutex);
                if (!first_error) first_error = std::current_exception();
                failed = true;
            }
        }
    }
};

// Helper threads that outlive a call, as pbrt-v4's ThreadPool and Embree's task scheduler keep
// theirs. Starting a thread per call cost little in itself (about 15 us), but on the virtual
// machine this is measured on, a new thread often began 0.5-4 ms after it was made: its
// processor had gone idle and took that long to wake, on a 25 ms render up to 15%. A helper that
// has finished a job waits for the next one awake for a while (kStayAwake), then sleeps until one
// comes: the load's, build's and render's calls mostly follow each other within that time. While
// awake it yields its processor between looks rather than spinning on the `pause` instruction: a
// loop of `pause` made the hypervisor take the processor away (a course scene's whole run went
// from 3.4 to 7-10 ms). Starting the helpers before the scene file is read, to have them awake
// sooner still, made small scenes' load and build slower (docs/performance.md).
class HelperPool {
public:
    // Made on first use, never destroyed (a static's destructor could run while another
    // thread's call uses it); its helpers are stopped at exit (stop_at_exit).
    static HelperPool& instance() {
        static HelperPool* pool = [] {
            HelperPool* made = new HelperPool;
            std::atexit([] { instance().stop_at_exit(); });
            return made;
        }();
        return *pool;
    }

    // Runs `job` on the caller (worker 0) and `helpers` helper threads (workers 1..helpers), and
    // returns true when done; false, at once, when the pool is running another job (a call from
    // another thread, or from inside a job), for the caller to do it some other way.
    bool try_run(Job& job, int helpers) {
        // A child of fork() (a death test's) has none of its parent's helpers; a call from
        // inside a job would find busy_ held by its own thread.
        if (getpid() != owner_ || t_in_job) return false;
        std::unique_lock<std::mutex> busy(busy_, std::try_to_lock);
        if (!busy.owns_lock()) return false;
        const InJob in_job;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            if (stopping_) return false;  // a call during exit, from another thread
            if (static_cast<int>(threads_.size()) < helpers) {
                const BlockAsynchronousSignals blocked;  // the helpers inherit the mask
                try {
                    while (static_cast<int>(threads_.size()) < helpers) {
                        const int index = static_cast<int>(threads_.size());
                        threads_.emplace_back([this, index] { helper_main(index); });
                    }
                } catch (const std::system_error&) {
                    // The system would start no more threads (ulimit -u, say): the job runs on
                    // those there are. Every result is the same for any number of threads.
                    helpers = static_cast<int>(threads_.size());
                }
            }
            job_ = &job;
            job_helpers_ = helpers;
            unfinished_.store(helpers);
            generation_.store(generation_.load() + 1, std::memory_order_release);
        }
        wake_.notify_all();
        job.run(0);
        // The helpers finish their last items at about the time the caller does.
        while (unfinished_.load(std::memory_order_acquire) != 0) std::this_thread::yield();
        return true;
    }

private:
    static constexpr std::chrono::milliseconds kStayAwake{kHelperStayAwakeMilliseconds};

    // Whether this thread is working on a pool job (as its caller or as a helper).
    static thread_local bool t_in_job;
    struct InJob {
        InJob() { t_in_job = true; }
        ~InJob() { t_in_job = false; }
    };

    // Helpers take no asynchronous signals: a signal for the process (the viewer's Ctrl-C, which
    // one thread waits for) must not land on a thread that happened to make them. Signals a
    // thread's own fault raises stay open, so that a crash in a helper is reported.
    struct BlockAsynchronousSignals {
        sigset_t before;
        BlockAsynchronousSignals() {
            sigset_t blocked;
            sigfillset(&blocked);
            for (int fault : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGTRAP, SIGSYS, SIGABRT, SIGPROF})
                sigdelset(&blocked, fault);
            pthread_sigmask(SIG_SETMASK, &blocked, &before);
        }
        ~BlockAsynchronousSignals() { pthread_sigmask(SIG_SETMASK, &before, nullptr); }
    };

    // Ends the helpers and waits for them, so that a process ends with one thread. Only when no
    // job is under way: otherwise (exit called from inside a job, or while another thread's
    // runs) the helpers are left to end with the process.
    void stop_at_exit() {
        if (getpid() != owner_ || t_in_job) return;  // a child of fork() has no helpers to stop
        std::unique_lock<std::mutex> busy(busy_, std::try_to_lock);
        if (!busy.owns_lock()) return;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            stopping_ = true;
            generation_.store(generation_.load() + 1, std::memory_order_release);
        }
        wake_.notify_all();
        for (std::thread& thread : threads_) thread.join();
        threads_.clear();
    }

    void helper_main(int index) {
        uint64_t seen = 0;
        bool worked = true;  // on the last job: then stay awake for a while
        for (;;) {
            // Awake for a while after a job it worked on, then asleep, until a new generation
            // (a job, or the end). A helper that a job did not need sleeps at once: after a call
            // with many threads, later calls with fewer do not keep the rest awake.
            const auto awake_until = std::chrono::steady_clock::now() + (worked ? kStayAwake : std::chrono::milliseconds(0));
            while (generation_.load(std::memory_order_acquire) == seen &&
                   std::chrono::steady_clock::now() < awake_until)
                std::this_thread::yield();
            Job* job;
            bool joins;
            {
                std::unique_lock<std::mutex> lock(mutex_);
                wake_.wait(lock, [&] { return generation_.load() != seen; });
                if (stopping_) return;
                // Read with the generation, under the lock: a job posted after it cannot be
                // mistaken for this one.
                seen = generation_.load();
                job = job_;
                joins = index < job_helpers_;
            }
            worked = joins;
            if (!joins) continue;
            {
                const InJob in_job;
                job->run(index + 1);
            }
            unfinished_.fetch_sub(1, std::memory_order_acq_rel);
        }
    }

    std::mutex busy_;  // held by the caller for a whole job
    std::mutex mutex_;
    std::condition_variable wake_;
    std::atomic<uint64_t> generation_{0};
    Job* job_ = nullptr;
    int job_helpers_ = 0;
    const pid_t owner_ = getpid();
    bool stopping_ = false;
    std::atomic<int> unfinished_{0};  // helpers of the current job still working on it
    std::vector<std::thread> threads_;
};

thread_local bool HelperPool::t_in_job = false;

// parallel_for without the pool: threads made for this call.
void run_on_new_threads(Job& job, int helpers) {
    std::vector<std::thread> threads;
    threads.reserve(static_cast<size_t>(helpers));
    try {
        for (int worker = 1; worker <= helpers; ++worker) threads.emplace_back([&job, worker] { job.run(worker); });
    } catch (const std::system_error&) {
        // No more threads to be had: those started and the caller share the items.
    }
    job.run(0);
    for (std::thread& thread : threads) thread.join();
}

}  // namespace

void parallel_for(size_t count, int threads, const std::function<void(size_t, int)>& work) {
    const int worker_count = static_cast<int>(std::min<size_t>(std::max(1, threads), std::max<size_t>(count, 1)));
    Job job;
    job.work = &work;
    job.count = count;
    const int helpers = worker_count - 1;
    if (helpers == 0)
        job.run(0);
    else if (!HelperPool::instance().try_run(job, helpers))
        run_on_new_threads(job, helpers);
    if (job.first_error) std::rethrow_exception(job.first_error);
}

void call_with_stack(size_t stack_bytes, const std::function<void()>& work) {
    struct Call {
        const std::function<void()>* work;
        std::exception_ptr error;
    } call{&work, nullptr};
    auto trampoline = [](void* argument) -> void* {
        Call* c = static_cast<Call*>(argument);
        try {
            (*c->work)();
        } catch (...) {
            c->error = std::current_exception();
        }
        return nullptr;
    };
    pthread_attr_t attributes;
    pthread_attr_init(&attributes);
    int status = pthread_attr_setstacksize(&attributes, stack_bytes);
    pthread_t thread;
    if (status == 0) status = pthread_create(&thread, &attributes, trampoline, &call);
    pthread_attr_destroy(&attributes);
    if (status != 0) {
        // No thread (a process limit, or no memory for the stack): run here, as before.
        work();
        return;
    }
    pthread_join(thread, nullptr);
    if (call.error) std::rethrow_exception(call.error);
}

void call_with_stack_for_depth(size_t levels, const std::function<void()>& work) {
    if (levels <= kShallowRecursionLevels)
        work();
    else
        call_with_stack(kDeepRecursionStackBytes, work);
}

}  // namespace raycast
