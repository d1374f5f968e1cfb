// `squint bench [--json]`: runs the Google Benchmark cases under bench/ and reports medians.
// A case's name is its JSON key; the key's suffix gives the unit: _us, _ms, _s (median time per
// iteration) or _per_s (iterations per second).
#ifdef SQUINT_WITH_BENCH
#include <benchmark/benchmark.h>

#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "command.hpp"
#include "squint/core/error.hpp"

namespace squint::app {
namespace {

double ToSeconds(double value, benchmark::TimeUnit unit) {
  switch (unit) {
    case benchmark::kNanosecond: return value * 1e-9;
    case benchmark::kMicrosecond: return value * 1e-6;
    case benchmark::kMillisecond: return value * 1e-3;
    case benchmark::kSecond: return value;
  }
  return value;
}

bool EndsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// Collects the median aggregate of each case, converted to the unit its name asks for.
class MedianCollector : public benchmark::BenchmarkReporter {
 public:
  bool ReportContext(const Context&) override { return true; }
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& run : runs) {
      if (run.error_occurred) continue;
      const bool is_median = run.run_type == Run::RT_Aggregate && run.aggregate_name == "median";
      const bool single = run.run_type == Run::RT_Iteration && run.repetitions <= 1;
      if (!is_median && !single) continue;
      std::string key = run.run_name.function_name;
      const double seconds = ToSeconds(run.GetAdjustedRealTime(), run.time_unit);
      double value = seconds;
      if (EndsWith(key, "_per_s")) value = seconds > 0 ? 1.0 / seconds : 0.0;
      else if (EndsWith(key, "_us")) value = seconds * 1e6;
      else if (EndsWith(key, "_ms")) value = seconds * 1e3;
      results[key] = value;
    }
  }
  std::map<std::string, double> results;
};

struct BenchOptions {
  bool json = false;
  bool quick = false;
  std::string filter = ".";
  int repetitions = 5;
};

void Run(const BenchOptions& opt) {
  std::vector<std::string> args = {"squint-bench", "--benchmark_filter=" + opt.filter};
  if (opt.quick) {
    args.push_back("--benchmark_min_time=0.01");
    args.push_back("--benchmark_repetitions=1");
  } else {
    args.push_back("--benchmark_repetitions=" + std::to_string(opt.repetitions));
    args.push_back("--benchmark_report_aggregates_only=true");
  }
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  int argc = static_cast<int>(argv.size());
  benchmark::Initialize(&argc, argv.data());
  MedianCollector collector;
  const std::size_t ran = benchmark::RunSpecifiedBenchmarks(&collector);
  if (ran == 0) throw Error("bench: no benchmark matches filter '" + opt.filter + "'");
  if (opt.json) {
    nlohmann::json out = nlohmann::json::object();
    for (auto& [k, v] : collector.results) out[k] = v;
    std::cout << out.dump(2) << "\n";
  } else {
    std::cout << "median over " << (opt.quick ? 1 : opt.repetitions) << " repetitions (one core):\n";
    for (auto& [k, v] : collector.results) std::cout << "  " << k << " = " << v << "\n";
  }
}

void Register(CLI::App& root) {
  auto opt = std::make_shared<BenchOptions>();
  CLI::App* cmd = root.add_subcommand("bench", "Time each stage on this machine and print medians");
  cmd->add_flag("--json", opt->json, "Print one JSON object of medians");
  cmd->add_flag("--quick", opt->quick, "One short repetition per case (a smoke run, not a measurement)");
  cmd->add_option("--filter", opt->filter, "Regular expression selecting the cases");
  cmd->add_option("--repetitions", opt->repetitions, "Repetitions whose median is reported")->check(kPositive);
  cmd->callback([opt] { Run(*opt); });
}

const CommandRegistrar kRegistrar(900, &Register);

}  // namespace
}  // namespace squint::app
#endif  // SQUINT_WITH_BENCH
