// A wall-clock stopwatch for the --stats line and the benchmarks.
#pragma once

#include <chrono>

namespace raycast {

class Timer {
public:
    Timer() : start_(std::chrono::steady_clock::now()) {}
    double elapsed_ms() const {
        return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_).count();
    }

private:
    std::chrono::steady_clock::time_point start_;
};

}  // namespace raycast
