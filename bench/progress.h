#pragma once
// One status line on stderr during long runs: what is running, the time so far and an estimate
// of what is left (time per finished configuration so far, times those still to come). Silent
// when stderr is not a terminal or with --quiet, so logs and pipes get only results.
#include <chrono>
#include <cstddef>
#include <string>

namespace trident::bench {

class Progress {
public:
    Progress(std::size_t total_configurations, bool quiet);
    ~Progress();
    Progress(const Progress&) = delete;
    Progress& operator=(const Progress&) = delete;

    /// Redraws the line with what is running now (at most ten times a second).
    void show(const std::string& what);
    void configuration_done() { ++done_; }

private:
    void clear();
    bool enabled_;
    std::size_t total_, done_ = 0;
    std::chrono::steady_clock::time_point start_, last_draw_;
    bool drawn_ = false;
};

}  // namespace trident::bench
