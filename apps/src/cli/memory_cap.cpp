// SPDX-License-Identifier: Apache-2.0
#include "cli/memory_cap.h"

#include <fmt/format.h>
#include <morph/exceptions.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cmath>
#include <limits>

namespace morphmill {

std::size_t physical_memory_bytes() {
  const long pages = ::sysconf(_SC_PHYS_PAGES);
  const long page_size = ::sysconf(_SC_PAGESIZE);
  if (pages <= 0 || page_size <= 0) return 0;
  return std::size_t(pages) * std::size_t(page_size);
}

double default_memory_cap_gib() {
  const std::size_t bytes = physical_memory_bytes();
  return bytes == 0 ? 8.0 : std::floor(double(bytes) / 2.0 / double(1 << 30) * 10.0) / 10.0;
}

CLI::Option* add_memory_cap_option(CLI::App* command, double& gib) {
  gib = default_memory_cap_gib();
  return command
      ->add_option("--memory-cap", gib,
                   "Refuse, before computing, work estimated to need more than this many GiB "
                   "(default: half of this machine's memory; at most all of it)")
      ->capture_default_str();
}

std::size_t memory_cap_bytes(double gib) {
  if (!(gib > 0.0)) throw morph::InputError("--memory-cap: must be > 0 GiB");
  const double requested = gib * double(std::size_t(1) << 30);
  const std::size_t machine = physical_memory_bytes();
  double limit = machine > 0 ? double(machine) : double(std::numeric_limits<std::size_t>::max() / 2);
  // An address-space limit (ulimit -v, a batch system's) caps what the process can get at all.
  struct rlimit address_space {};
  if (::getrlimit(RLIMIT_AS, &address_space) == 0 && address_space.rlim_cur != RLIM_INFINITY)
    limit = std::min(limit, 0.9 * double(address_space.rlim_cur));
  return std::size_t(std::min(requested, limit));
}

std::string describe_bytes(double bytes) {
  if (bytes >= double(std::size_t(10) << 30)) return fmt::format("{:.1f} GiB", bytes / double(1 << 30));
  return fmt::format("{:.0f} MiB", std::ceil(bytes / double(1 << 20)));
}

}  // namespace morphmill
