// SPDX-License-Identifier: Apache-2.0
// PLY meshes through morphmill's reader (the format follows the name's extension).
#include <morphmill/mesh_io.h>

#include "contract.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return within_contract([&] { morphmill::read_mesh_bytes(bytes(data, size), "fuzz.ply"); });
}
