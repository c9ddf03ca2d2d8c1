#include "commands.h"

namespace morphmill {

void register_verify_command(CLI::App& /*app*/) {
  // Placeholder until this command group is implemented.
}

}  // namespace morphmill
