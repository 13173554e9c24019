#include "bench/machine.h"

#include <fmt/format.h>
#include <tbb/info.h>

#include <ctime>
#include <fstream>
#include <set>
#include <utility>

#if TRIDENT_HAVE_EMBREE
#include <embree3/rtcore_config.h>
#endif

namespace trident::bench {
namespace {

std::string value_after_colon(const std::string& line) {
    const auto colon = line.find(':');
    if (colon == std::string::npos) return {};
    const auto start = line.find_first_not_of(" \t", colon + 1);
    return start == std::string::npos ? std::string{} : line.substr(start);
}

void read_cpuinfo(MachineInfo& info) {
    std::ifstream cpuinfo("/proc/cpuinfo");
    std::set<std::pair<std::string, std::string>> cores;
    std::string line, physical_id;
    while (std::getline(cpuinfo, line)) {
        if (line.starts_with("model name") && info.cpu_model.empty()) info.cpu_model = value_after_colon(line);
        if (line.starts_with("physical id")) physical_id = value_after_colon(line);
        if (line.starts_with("core id")) cores.emplace(physical_id, value_after_colon(line));
    }
    if (info.cpu_model.empty()) info.cpu_model = "unknown CPU";
    info.physical_cores = unsigned(cores.size());
}

std::string now_utc() {
    const std::time_t now = std::time(nullptr);
    std::tm utc{};
    gmtime_r(&now, &utc);
    char text[32];
    std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &utc);
    return text;
}

}  // namespace

MachineInfo describe_machine() {
    MachineInfo info;
    read_cpuinfo(info);
    info.hardware_threads = unsigned(tbb::info::default_concurrency());
    info.date_utc = now_utc();
#if defined(__clang__)
    info.compiler = fmt::format("clang {}", __clang_version__);
#elif defined(__GNUC__)
    info.compiler = fmt::format("gcc {}", __VERSION__);
#endif
#if TRIDENT_HAVE_EMBREE
    info.embree_version = RTC_VERSION_STRING;
#endif
    return info;
}

}  // namespace trident::bench
