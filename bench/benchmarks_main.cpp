// Standalone Google Benchmark runner over the same cases as `squint bench`.
#include <benchmark/benchmark.h>

BENCHMARK_MAIN();
