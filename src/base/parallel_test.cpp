// Tests for parallel_for (base/parallel.h), which the renderer (tiles), the OBJ loader (chunks)
// and the BVH builder rely on: every item must be visited exactly once whatever the thread count,
// worker numbers must stay in [0, threads), the work must really run on several threads, an
// exception thrown by one item must reach the caller instead of terminating the program, and the
// helper threads kept between calls must serve one call at a time and never be waited for where
// they do not exist.
#include "base/parallel.h"

#include <gtest/gtest.h>
#include <pthread.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace raycast {
namespace {

TEST(ParallelFor, HardwareThreadsIsAtLeastOne) { EXPECT_GE(hardware_threads(), 1); }

TEST(ParallelFor, VisitsEveryItemExactlyOnceForAnyThreadCount) {
    for (int threads : {1, 2, 3, 8}) {
        for (size_t count : {size_t{0}, size_t{1}, size_t{1000}}) {
            SCOPED_TRACE("threads " + std::to_string(threads) + ", count " + std::to_string(count));
            std::vector<std::atomic<int>> visits(count);
            for (auto& v : visits) v = 0;
            std::atomic<int> bad_worker{0};
            std::atomic<size_t> calls{0};
            parallel_for(count, threads, [&](size_t item, int worker) {
                ++calls;
                if (worker < 0 || worker >= threads) ++bad_worker;
                ASSERT_LT(item, count);
                ++visits[item];
            });
            EXPECT_EQ(calls.load(), count);
            EXPECT_EQ(bad_worker.load(), 0);
            for (size_t i = 0; i < count; ++i) ASSERT_EQ(visits[i].load(), 1) << "item " << i;
        }
    }
}

TEST(ParallelFor, OneThreadRunsInOrderOnTheCallersThread) {
    const std::thread::id caller = std::this_thread::get_id();
    std::vector<size_t> order;
    bool other_thread = false;
    parallel_for(50, 1, [&](size_t item, int worker) {
        EXPECT_EQ(worker, 0);
        other_thread |= std::this_thread::get_id() != caller;
        order.push_back(item);
    });
    EXPECT_FALSE(other_thread);
    ASSERT_EQ(order.size(), 50u);
    for (size_t i = 0; i < order.size(); ++i) EXPECT_EQ(order[i], i);
}

TEST(ParallelFor, RunsItemsOnDistinctWorkersAtTheSameTime) {
    // Each of 4 items waits until all 4 have started. A worker claims one item at a time, so this
    // only completes if 4 workers run at once, each with its own worker number. The wait has a
    // generous deadline only so that a broken implementation fails instead of hanging.
    constexpr int kThreads = 4;
    std::mutex mutex;
    std::condition_variable all_started;
    int started = 0;
    bool timed_out = false;
    std::set<int> workers;
    std::set<std::thread::id> thread_ids;
    parallel_for(kThreads, kThreads, [&](size_t, int worker) {
        std::unique_lock<std::mutex> lock(mutex);
        ++started;
        workers.insert(worker);
        thread_ids.insert(std::this_thread::get_id());
        all_started.notify_all();
        if (!all_started.wait_for(lock, std::chrono::seconds(30), [&] { return started == kThreads; }))
            timed_out = true;
    });
    EXPECT_FALSE(timed_out);
    EXPECT_EQ(workers, (std::set<int>{0, 1, 2, 3}));
    EXPECT_EQ(thread_ids.size(), 4u);
}

TEST(ParallelFor, RethrowsAnExceptionFromATaskInTheCaller) {
    for (int threads : {1, 2, 3, 8}) {
        SCOPED_TRACE("threads " + std::to_string(threads));
        std::atomic<size_t> calls{0};
        try {
            parallel_for(1000, threads, [&](size_t item, int) {
                ++calls;
                if (item == 500) throw std::runtime_error("item 500 failed");
            });
            ADD_FAILURE() << "no exception reached the caller";
        } catch (const std::runtime_error& e) {
            EXPECT_STREQ(e.what(), "item 500 failed");
        }
        EXPECT_GE(calls.load(), 1u);
        EXPECT_LE(calls.load(), 1000u);
    }
}

TEST(ParallelFor, OneThreadSkipsTheItemsAfterAFailure) {
    // Header: if a call throws, the remaining items are skipped. With one thread "remaining" is
    // exactly the items after the one that threw.
    std::vector<size_t> seen;
    EXPECT_THROW(parallel_for(100, 1,
                              [&](size_t item, int) {
                                  seen.push_back(item);
                                  if (item == 10) throw std::logic_error("stop");
                              }),
                 std::logic_error);
    ASSERT_EQ(seen.size(), 11u);
    EXPECT_EQ(seen.back(), 10u);
}

TEST(ParallelFor, WhenEveryTaskThrowsExactlyOneExceptionArrives) {
    int caught = 0;
    try {
        parallel_for(64, 8, [](size_t item, int) { throw std::runtime_error("failed " + std::to_string(item)); });
    } catch (const std::runtime_error& e) {
        ++caught;
        EXPECT_EQ(std::string(e.what()).rfind("failed ", 0), 0u) << e.what();
    }
    EXPECT_EQ(caught, 1);
}

TEST(ParallelFor, NonStandardExceptionTypesAreRethrownToo) {
    EXPECT_THROW(parallel_for(10, 3, [](size_t item, int) { if (item == 3) throw 42; }), int);
}

// The helper threads are kept: a second call runs on the threads of the first (parallel.cpp
// keeps them because a new thread often started milliseconds late). Each thread counts the calls
// it has worked on in a thread_local (thread ids are no proof: a new thread may reuse the id of
// one that has ended).
TEST(ParallelFor, KeepsItsHelperThreadsFromOneCallToTheNext) {
    static thread_local int calls_seen = 0;
    auto helpers_calls = [] {
        std::mutex mutex;
        std::multiset<int> seen;
        const std::thread::id caller = std::this_thread::get_id();
        // Items that wait for each other, so that every worker takes part, once.
        std::atomic<int> started{0};
        parallel_for(3, 3, [&](size_t, int) {
            ++started;
            const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
            while (started.load() < 3 && std::chrono::steady_clock::now() < deadline) std::this_thread::yield();
            std::lock_guard<std::mutex> lock(mutex);
            if (std::this_thread::get_id() != caller) seen.insert(++calls_seen);
        });
        return seen;
    };
    const std::multiset<int> first = helpers_calls();
    ASSERT_EQ(first.size(), 2u);
    std::multiset<int> expected;
    for (int calls : first) expected.insert(calls + 1);
    EXPECT_EQ(helpers_calls(), expected);
}

// Only one call at a time uses the kept threads; another, from another thread or from inside
// the work, gets threads of its own and must still see every item once.
TEST(ParallelFor, CallsFromSeveralThreadsAndNestedCallsEachVisitEveryItemOnce) {
    constexpr size_t kOuter = 8, kInner = 200;
    auto nested = [&](std::vector<std::atomic<int>>& visits) {
        parallel_for(kOuter, 3, [&](size_t outer, int) {
            parallel_for(kInner, 2, [&](size_t inner, int) { ++visits[outer * kInner + inner]; });
        });
    };
    std::vector<std::atomic<int>> a(kOuter * kInner), b(kOuter * kInner);
    for (auto& v : a) v = 0;
    for (auto& v : b) v = 0;
    std::thread other([&] { nested(b); });
    nested(a);
    other.join();
    for (size_t i = 0; i < a.size(); ++i) {
        ASSERT_EQ(a[i].load(), 1) << "item " << i;
        ASSERT_EQ(b[i].load(), 1) << "item " << i;
    }
}

// A signal sent to the process must reach a thread that expects it (the viewer has one thread
// wait for Ctrl-C, with the signal blocked everywhere else), never a kept helper made while it
// was unblocked; a fault in a helper must still be reported (its signal open); and the caller's
// own mask is as it was.
TEST(ParallelFor, HelperThreadsTakeNoSignalsButTheirOwnFaults) {
    sigset_t caller_before, caller_after;
    pthread_sigmask(SIG_BLOCK, nullptr, &caller_before);
    std::atomic<int> helpers_taking_sigint{0}, helpers_blocking_segv{0}, helper_items{0};
    std::atomic<int> started{0};
    parallel_for(2, 2, [&](size_t, int worker) {
        ++started;
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
        while (started.load() < 2 && std::chrono::steady_clock::now() < deadline) std::this_thread::yield();
        if (worker == 0) return;
        ++helper_items;
        sigset_t mask;
        pthread_sigmask(SIG_BLOCK, nullptr, &mask);
        if (!sigismember(&mask, SIGINT)) ++helpers_taking_sigint;
        if (sigismember(&mask, SIGSEGV)) ++helpers_blocking_segv;
    });
    pthread_sigmask(SIG_BLOCK, nullptr, &caller_after);
    EXPECT_EQ(helper_items.load(), 1);
    EXPECT_EQ(helpers_taking_sigint.load(), 0);
    EXPECT_EQ(helpers_blocking_segv.load(), 0);
    EXPECT_EQ(sigismember(&caller_after, SIGINT), sigismember(&caller_before, SIGINT));
}

// A child of fork() has only the thread that forked: the kept helpers are not there, and a call
// must not wait for them. A call first, so that the parent has helpers when it forks.
TEST(ParallelFor, WorksInAChildOfFork) {
    parallel_for(10, 3, [](size_t, int) {});
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        alarm(30);  // a hang becomes a failure
        std::atomic<size_t> sum{0};
        parallel_for(1000, 3, [&](size_t item, int) { sum += item; });
        _exit(sum.load() == 999 * 1000 / 2 ? 0 : 1);
    }
    int status = 0;
    ASSERT_EQ(waitpid(child, &status, 0), child);
    ASSERT_TRUE(WIFEXITED(status)) << "the child was killed (signal " << (WIFSIGNALED(status) ? WTERMSIG(status) : 0)
                                   << ")";
    EXPECT_EQ(WEXITSTATUS(status), 0);
}

// Shallow work runs on the caller's own stack (a thread with a 128 MiB stack cost ~115 µs to
// start); deeper work gets that thread, and its exception comes back here.
TEST(CallWithStackForDepthTest, OnlyDeepWorkGetsAThreadOfItsOwn) {
    const std::thread::id caller = std::this_thread::get_id();
    std::thread::id ran_on;
    call_with_stack_for_depth(kShallowRecursionLevels, [&] { ran_on = std::this_thread::get_id(); });
    EXPECT_EQ(ran_on, caller);
    call_with_stack_for_depth(kShallowRecursionLevels + 1, [&] { ran_on = std::this_thread::get_id(); });
    EXPECT_NE(ran_on, caller);
    EXPECT_THROW(call_with_stack_for_depth(1000, [] { throw std::runtime_error("deep"); }), std::runtime_error);
    EXPECT_THROW(call_with_stack_for_depth(1, [] { throw std::runtime_error("shallow"); }), std::runtime_error);
}

}  // namespace
}  // namespace raycast
