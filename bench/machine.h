#pragma once
// What a result needs to say about where it was measured.
#include <string>

namespace trident::bench {

struct MachineInfo {
    std::string cpu_model;          // "model name" of /proc/cpuinfo
    unsigned hardware_threads = 0;  // what oneTBB would use by default
    unsigned physical_cores = 0;    // distinct (physical id, core id) pairs; 0 when unknown
    std::string date_utc;           // ISO 8601, when the run started
    std::string compiler;
    std::string embree_version;  // empty without Embree
};

MachineInfo describe_machine();

}  // namespace trident::bench
