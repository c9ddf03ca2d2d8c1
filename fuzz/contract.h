// SPDX-License-Identifier: Apache-2.0
#pragma once
// The error contract every harness checks: bad input may only end in the exceptions that
// morphmill turns into exit 2. Anything else escapes LLVMFuzzerTestOneInput and libFuzzer
// reports it (uncaught exception -> abort) with the input that caused it.
#include <morph/exceptions.h>

#include <cstddef>
#include <cstdint>
#include <string>

template <class Read>
int within_contract(Read read) {
  try {
    read();
  } catch (const morph::InputError&) {
  } catch (const morph::IoError&) {
  } catch (const morph::LimitError&) {
  }
  return 0;
}

inline std::string bytes(const std::uint8_t* data, std::size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}
