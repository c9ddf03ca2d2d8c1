// SPDX-License-Identifier: Apache-2.0
#pragma once
// --memory-cap: how much memory a command may plan to use, checked against an estimate made
// from the job alone before any long computation starts.
#include <CLI/CLI.hpp>

#include <cstddef>
#include <string>

namespace morphmill {

/// The machine's physical memory in bytes (0 if unknown).
std::size_t physical_memory_bytes();

/// The default cap: half of the machine's physical memory, in GiB (8 GiB if unknown).
double default_memory_cap_gib();

/// Adds `--memory-cap GIB` (default: default_memory_cap_gib()) to `command`.
CLI::Option* add_memory_cap_option(CLI::App* command, double& gib);

/// The cap in bytes: `gib` (> 0; inf means no cap of the user's) but never more than the machine's
/// physical memory, since no estimate above that can be met. Throws morph::InputError for <= 0
/// or NaN.
std::size_t memory_cap_bytes(double gib);

/// "1234 MiB" / "12.3 GiB".
std::string describe_bytes(double bytes);

}  // namespace morphmill
