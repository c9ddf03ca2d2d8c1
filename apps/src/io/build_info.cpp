// SPDX-License-Identifier: Apache-2.0
#include "io/build_info.h"

#include <morphmill_source_commit.h>

namespace morphmill {

std::string program_version() {
  return MORPHMILL_VERSION;
}

std::string source_commit() {
  return MORPHMILL_SOURCE_COMMIT;
}

std::string git_describe() {
  const std::string described = MORPHMILL_GIT_DESCRIBE;
  return described.empty() ? std::string(MORPHMILL_VERSION) : described;
}

}  // namespace morphmill
