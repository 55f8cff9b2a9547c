#include "base/parallel.h"

#include <algorithm>
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

}  // namespace raycast
