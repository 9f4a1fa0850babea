#pragma once
// Google Benchmark's console output plus a record of items/s per run name, so that a benchmark
// program can print same-run ratios after the table.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace shvol::bench {

class RatioReporter : public benchmark::ConsoleReporter {
  public:
    std::map<std::string, double> rate;
    void ReportRuns(const std::vector<Run>& runs) override {
        for (const Run& r : runs) {
            auto it = r.counters.find("items_per_second");
            if (it != r.counters.end()) rate[r.benchmark_name()] = it->second;
        }
        ConsoleReporter::ReportRuns(runs);
    }
    /// Prints rate(a) / rate(b) if both ran.
    void ratio(const std::string& a, const std::string& b) const {
        const auto x = rate.find(a), y = rate.find(b);
        if (x == rate.end() || y == rate.end()) return;
        std::printf("  %-34s / %-28s = %.3f\n", a.c_str(), b.c_str(), x->second / y->second);
    }
};

/// Runs the registered benchmarks and then prints the same-run ratio a / b of each pair.
inline int runWithRatios(int argc, char** argv,
                         const std::vector<std::pair<std::string, std::string>>& pairs,
                         const char* title = "Same-run ratios (items/s):") {
    benchmark::Initialize(&argc, argv);
    RatioReporter reporter;
    benchmark::RunSpecifiedBenchmarks(&reporter);
    std::printf("\n%s\n", title);
    for (const auto& [a, b] : pairs) reporter.ratio(a, b);
    return 0;
}

}  // namespace shvol::bench
