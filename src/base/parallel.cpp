#include "base/parallel.h"

#include <pthread.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace raycast {

int hardware_threads() { return std::max(1u, std::thread::hardware_concurrency()); }

void parallel_for(size_t count, int threads, const std::function<void(size_t, int)>& work) {
    const int worker_count = static_cast<int>(std::min<size_t>(std::max(1, threads), std::max<size_t>(count, 1)));
    std::atomic<size_t> next{0};
    std::atomic<bool> failed{false};
    std::exception_ptr first_error;
    std::mutex error_mutex;
    auto run = [&](int worker) {
        for (;;) {
            const size_t item = next.fetch_add(1);
            if (item >= count || failed.load()) return;
            try {
                work(item, worker);
            } catch (...) {
                std::lock_guard<std::mutex> lock(error_mutex);
                if (!first_error) first_error = std::current_exception();
                failed = true;
            }
        }
    };
    std::vector<std::thread> helpers;
    helpers.reserve(static_cast<size_t>(worker_count - 1));
    for (int worker = 1; worker < worker_count; ++worker) helpers.emplace_back(run, worker);
    run(0);
    for (std::thread& helper : helpers) helper.join();
    if (first_error) std::rethrow_exception(first_error);
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

}  // namespace raycast
