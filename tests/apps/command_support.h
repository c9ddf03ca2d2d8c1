// SPDX-License-Identifier: Apache-2.0
#pragma once
// Running the morphmill binary from tests: exit code and combined output.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <system_error>
#include <vector>

namespace morphmill_test {

/// Whether a child's peak memory is the program's own: under AddressSanitizer (make test-asan)
/// its shadow memory and quarantine add a multiple, so tests that hold a measured peak to a
/// figure skip that check there (the rest of each test still runs).
#ifdef MORPHMILL_SANITIZED
constexpr bool kPeakMemoryIsTheProgramsOwn = false;
#else
constexpr bool kPeakMemoryIsTheProgramsOwn = true;
#endif

struct CommandResult {
  int exit_code = -1;  ///< -1 if the command could not run or did not exit normally
  std::string output;  ///< standard output and standard error together
};

inline CommandResult run_command(const std::string& command) {
  CommandResult result;
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return result;
  std::array<char, 4096> buffer{};
  while (fgets(buffer.data(), buffer.size(), pipe)) result.output += buffer.data();
  const int status = pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

/// A fresh, empty directory under the system temporary directory, unique to this process: ctest
/// runs every test in its own process, several at once.
/// Every scratch directory of this test process, removed when it exits (a command's outputs can be
/// hundreds of MB; test runs must not fill /tmp). MORPHMILL_KEEP_SCRATCH=1 keeps them to look at.
struct ScratchDirs {
  std::vector<std::filesystem::path> dirs;
  ~ScratchDirs() {
    if (std::getenv("MORPHMILL_KEEP_SCRATCH")) return;
    std::error_code ignored;
    for (const std::filesystem::path& dir : dirs) std::filesystem::remove_all(dir, ignored);
  }
};
inline ScratchDirs& scratch_dirs() {
  static ScratchDirs all;
  return all;
}

inline std::filesystem::path scratch_dir(const std::string& suite, const std::string& name) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                    ("morphmill_" + suite + "_" + std::to_string(::getpid()) + "_" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  scratch_dirs().dirs.push_back(dir);
  return dir;
}

/// A fixture giving each test its own empty scratch directory, removed afterwards.
class ScratchDirTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = scratch_dir("fixture", ::testing::UnitTest::GetInstance()->current_test_info()->name());
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  /// Writes `text` to `name` in the scratch directory and returns its path.
  std::string write_text(const std::string& name, const std::string& text) const {
    std::ofstream(path(name), std::ios::binary) << text;
    return path(name);
  }
  std::filesystem::path dir_;
};

struct Measured {
  int exit_code = -1;
  double peak_bytes = 0.0;
  std::string out, err;
};

/// Runs morphmill with `arguments` (a shell word list), stdout/stderr to files in `dir`, and
/// returns the child's peak resident memory.
inline Measured run_measured(const std::string& arguments, const std::filesystem::path& dir) {
  const std::string out = (dir / "out.txt").string(), err = (dir / "err.txt").string();
  const pid_t pid = ::fork();
  if (pid == 0) {
    const std::string command = "cd '" + dir.string() + "' && exec '" + MORPHMILL_BINARY + "' " + arguments +
                                " > '" + out + "' 2> '" + err + "' < /dev/null";
    ::execl("/bin/sh", "sh", "-c", command.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  Measured m;
  int status = 0;
  struct rusage usage {};
  if (pid < 0 || ::wait4(pid, &status, 0, &usage) != pid) return m;
  m.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  m.peak_bytes = double(usage.ru_maxrss) * 1024.0;
  std::ifstream o(out), e(err);
  m.out.assign(std::istreambuf_iterator<char>(o), {});
  m.err.assign(std::istreambuf_iterator<char>(e), {});
  return m;
}

/// The "memory: estimated N MiB|GiB" a command's summary prints, in MiB; -1 when absent.
inline double estimated_mib(const std::string& summary) {
  std::smatch match;
  if (!std::regex_search(summary, match, std::regex(R"(memory: estimated ([0-9.]+) (MiB|GiB))"))) return -1.0;
  return std::stod(match[1]) * (match[2] == "GiB" ? 1024.0 : 1.0);
}

}  // namespace morphmill_test
