// SPDX-License-Identifier: Apache-2.0
#pragma once
// What this build of morphmill is: its version and the source commit it was built from.
#include <string>

namespace morphmill {

/// The project version (CMake's PROJECT_VERSION), e.g. "0.1.0".
std::string program_version();

/// The git commit the build was made from, with "-modified" when tracked files differed from it,
/// or "unknown" when the source was not a git checkout. Read at build time.
std::string source_commit();

/// `git describe --always --dirty --tags` of the source at build time (e.g. "v0.2-14-g1a2b3c4" or
/// "1a2b3c4-dirty"), or the project version when the source was not a git checkout.
std::string git_describe();

}  // namespace morphmill
