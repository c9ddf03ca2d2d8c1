// SPDX-License-Identifier: Apache-2.0
// Job files: JSON syntax, nesting, numbers, every key's checks (G-code and mesh paths resolve
// relative to the working directory, which `make fuzz` sets to a scratch directory).
#include <morphmill/job_io.h>

#include "contract.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return within_contract([&] { morphmill::parse_job_text(bytes(data, size), "fuzz.json"); });
}
