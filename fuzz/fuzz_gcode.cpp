// SPDX-License-Identifier: Apache-2.0
// G-code programs through morph's reader with the default options.
#include <morph/gcode.h>

#include <sstream>

#include "contract.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return within_contract([&] {
    std::istringstream in(bytes(data, size));
    morph::parse_gcode(in, "fuzz.nc");
  });
}
