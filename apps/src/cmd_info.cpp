#include "commands.h"

namespace morphmill {

void register_info_commands(CLI::App& /*app*/) {
  // Placeholder until this command group is implemented.
}

}  // namespace morphmill
