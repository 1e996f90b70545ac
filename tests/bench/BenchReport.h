#pragma once
// Prints benchmark results as a table row for people and a `BENCH <name> <value>` line for tools.
#include <chrono>
#include <cstdio>
#include <string>

namespace mwb::bench {

inline void report(const std::string& name, double value, const std::string& unit, const std::string& note = "") {
    std::printf("  %-36s %14.4f  %-12s %s\n", name.c_str(), value, unit.c_str(), note.c_str());
    std::printf("BENCH %s %.6g\n", name.c_str(), value);
    std::fflush(stdout);
}

inline double seconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

inline std::string data_path(const std::string& name) { return std::string(MWB_BENCH_DIR) + "/" + name; }

}  // namespace mwb::bench
