// SPDX-License-Identifier: Apache-2.0
// G-code programs through morph's reader. The bounds on loops, re-run lines and moves are a
// hundredth of the defaults: a program that loops to its bound is refused the same way (the unit
// tests check each bound at its value), and under the fuzzer's instrumentation a default bound
// (10^6 loop iterations: 2.7 s in a release build) takes longer than its per-input timeout.
#include <morph/gcode.h>

#include <sstream>

#include "contract.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return within_contract([&] {
    std::istringstream in(bytes(data, size));
    morph::GcodeOptions options;
    options.max_loop_iterations = 10'000;
    options.max_blocks = 1'000'000;
    options.max_moves = 200'000;
    morph::parse_gcode(in, "fuzz.nc", options);
  });
}
