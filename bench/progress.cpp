#include "bench/progress.h"

#include <fmt/format.h>
#include <unistd.h>

#include <cstdio>

namespace trident::bench {
namespace {

std::string format_duration(double seconds) {
    const auto s = static_cast<long long>(seconds + 0.5);
    if (s < 60) return fmt::format("{}s", s);
    if (s < 3600) return fmt::format("{}m{:02}s", s / 60, s % 60);
    return fmt::format("{}h{:02}m", s / 3600, (s / 60) % 60);
}

}  // namespace

Progress::Progress(std::size_t total_configurations, bool quiet)
    : enabled_(!quiet && ::isatty(STDERR_FILENO)),
      total_(total_configurations),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_ - std::chrono::seconds(1)) {}

Progress::~Progress() { clear(); }

void Progress::show(const std::string& what) {
    if (!enabled_) return;
    const auto now = std::chrono::steady_clock::now();
    if (now - last_draw_ < std::chrono::milliseconds(100)) return;
    last_draw_ = now;
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    const std::string left =
        done_ ? fmt::format("~{} left", format_duration(elapsed / double(done_) * double(total_ - done_)))
              : "estimating";
    fmt::print(stderr, "\r\x1b[K[{}/{}] {} | {} elapsed, {}", done_ + 1 > total_ ? total_ : done_ + 1, total_, what,
               format_duration(elapsed), left);
    std::fflush(stderr);
    drawn_ = true;
}

void Progress::clear() {
    if (!drawn_) return;
    fmt::print(stderr, "\r\x1b[K");
    std::fflush(stderr);
    drawn_ = false;
}

}  // namespace trident::bench
