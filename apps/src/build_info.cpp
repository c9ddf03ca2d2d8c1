// SPDX-License-Identifier: Apache-2.0
#include "build_info.h"

#include <morphmill_source_commit.h>

namespace morphmill {

std::string program_version() {
  return MORPHMILL_VERSION;
}

std::string source_commit() {
  return MORPHMILL_SOURCE_COMMIT;
}

}  // namespace morphmill
