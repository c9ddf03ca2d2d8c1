// SPDX-License-Identifier: Apache-2.0
#pragma once
// Which surface generator a command runs (`--generator`): 1, today's sweep-patch generator
// (morph::erode: sphere and ball-end tools, every stock), or 2, generator 2 (morph::erode2: the
// union of exact sweep polytopes, closed by construction; every tool of revolution, every stock).
// One place decides what each can build, so erode, verify, compare, stress and study agree.
#include <morph/erode.h>
#include <morph/job.h>

#include <string>

namespace morphmill {

/// The generator commands run when --generator is not given.
constexpr int kDefaultGenerator = 1;

/// The text of every command's --generator option.
extern const char* const kGeneratorOptionHelp;

/// Throws morph::InputError unless `generator` is 1 or 2.
void check_generator(int generator);

/// Why `generator` cannot build `job`, as a sentence naming the move and tool or the stock ("" if
/// it can build it all).
std::string why_generator_cannot_build(const morph::Job& job, int generator);

/// Runs the generator chosen (checked with check_generator).
morph::ErodeResult run_generator(const morph::Job& job, const morph::ErodeOptions& options, int generator);

}  // namespace morphmill
