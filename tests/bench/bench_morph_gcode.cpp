// SPDX-License-Identifier: Apache-2.0
// G-code reader throughput. Run: bench_morph --benchmark_filter=Gcode
// Reports lines/s (items_per_second) and bytes/s; the file is read into memory once, so this is
// the parse alone (lexing, modal state, move construction), not the disk.
#include <benchmark/benchmark.h>
#include <morph/gcode.h>

#include <cstdio>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>

namespace {

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

void parse_text(benchmark::State& state, const std::string& path, const std::string& text) {
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

void parse_file(benchmark::State& state, const std::string& path) {
  const std::string text = slurp(path);
  if (text.empty()) {
    state.SkipWithError(("cannot read " + path).c_str());
    return;
  }
  parse_text(state, path, text);
}

/// A million lines of CAM-style code: feed moves with three axis words, an arc every tenth line,
/// a comment every hundredth (linear time: lines/s should match the small files').
std::string million_lines() {
  std::string text = "G21 G90 G17 F500\nG0 X0 Y0 Z5\n";
  char line[96];
  for (int k = 0; k < 1'000'000; ++k) {
    const double x = (k % 200) * 0.5, y = (k / 200) * 0.01;
    if (k % 100 == 0)
      text += "(row " + std::to_string(k / 100) + ")\n";
    else if (k % 10 == 0)
      std::snprintf(line, sizeof line, "G2 X%.3f Y%.3f I0.25 J0\n", x, y), text += line;
    else
      std::snprintf(line, sizeof line, "G1 X%.3f Y%.3f Z%.3f\n", x, y, -0.1 * (k % 7)), text += line;
  }
  return text;
}

void BM_GcodeParseMillionLines(benchmark::State& state) {
  static const std::string text = million_lines();
  parse_text(state, "million.ngc", text);
}
BENCHMARK(BM_GcodeParseMillionLines)->Unit(benchmark::kMillisecond);

/// The same number of moves from a six-line O-word loop with expressions: control flow and
/// expression evaluation per executed line.
void BM_GcodeLoopMillionMoves(benchmark::State& state) {
  const std::string text =
      "G21 G90 F500\nG0 X0 Y0 Z5\n#1 = 0\no1 while [#1 LT 1000000]\n"
      "G1 X[#1 MOD 200 * 0.5] Y[FIX[#1 / 200] * 0.01] Z[-0.1 * [#1 MOD 7]]\n#1 = [#1 + 1]\no1 endwhile\nM2\n";
  morph::GcodeOptions options;
  options.max_loop_iterations = 2'000'000;
  std::size_t moves = 0;
  for (auto _ : state) {
    std::istringstream in(text);
    const morph::GcodeResult result = morph::parse_gcode(in, "loop.ngc", options);
    moves = result.path.moves.size();
    benchmark::DoNotOptimize(result.path.moves.data());
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * moves));
  state.counters["moves"] = static_cast<double>(moves);
}
BENCHMARK(BM_GcodeLoopMillionMoves)->Unit(benchmark::kMillisecond);

void BM_GcodeParseBear(benchmark::State& state) {
  parse_file(state, std::string(MORPHMILL_SHARED_DIR) + "/gcode/bear.nc");
}
BENCHMARK(BM_GcodeParseBear)->Unit(benchmark::kMillisecond);

void BM_GcodeParse3DChips(benchmark::State& state) {
  parse_file(state, std::string(MORPHMILL_TEST_DATA) + "/gcode/3D_Chips.ngc");
}
BENCHMARK(BM_GcodeParse3DChips)->Unit(benchmark::kMillisecond);

}  // namespace
