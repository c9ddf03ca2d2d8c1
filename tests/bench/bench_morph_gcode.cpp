// G-code reader throughput. Run: bench_morph --benchmark_filter=Gcode
// Reports lines/s (items_per_second) and bytes/s; the file is read into memory once, so this is
// the parse alone (lexing, modal state, move construction), not the disk.
#include <benchmark/benchmark.h>
#include <morph/gcode.h>

#include <fstream>
#include <iterator>
#include <sstream>
#include <string>

namespace {

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

void parse_file(benchmark::State& state, const std::string& path) {
  const std::string text = slurp(path);
  if (text.empty()) {
    state.SkipWithError(("cannot read " + path).c_str());
    return;
  }
  std::size_t lines = 0, moves = 0;
  for (auto _ : state) {
    std::istringstream in(text);
    const morph::GcodeResult result = morph::parse_gcode(in, path);
    lines = result.line_count;
    moves = result.path.moves.size();
    benchmark::DoNotOptimize(result.path.moves.data());
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * lines));
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations() * text.size()));
  state.counters["lines"] = static_cast<double>(lines);
  state.counters["moves"] = static_cast<double>(moves);
}

void BM_GcodeParseBear(benchmark::State& state) {
  parse_file(state, std::string(MORPHMILL_SHARED_DIR) + "/gcode/bear.nc");
}
BENCHMARK(BM_GcodeParseBear)->Unit(benchmark::kMillisecond);

void BM_GcodeParse3DChips(benchmark::State& state) {
  parse_file(state, std::string(MORPHMILL_TEST_DATA) + "/gcode/3D_Chips.ngc");
}
BENCHMARK(BM_GcodeParse3DChips)->Unit(benchmark::kMillisecond);

}  // namespace
