// SPDX-License-Identifier: Apache-2.0
// The guarded file path: regular files only (refused by name, without blocking), sizes capped
// before anything is allocated, and atomic, checked writes. Reproducers of
// ../shared/repro/hostile/ (FIFOs, /dev/zero, directories, /dev/full, unwritable places).
#include <fcntl.h>
#include <gtest/gtest.h>
#include <morph/exceptions.h>
#include <morph/file_io.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>

namespace {

namespace fs = std::filesystem;

class FileIo : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("morph_file_io_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::string slurp(const std::string& name) const {
    std::ifstream in(path(name), std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  }
  fs::path dir_;
};

template <class Error, class F>
std::string error_of(F f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  } catch (const std::exception& e) {
    return std::string("wrong exception type: ") + e.what();
  }
  return "no exception";
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST_F(FileIo, ReadsARegularFileWhole) {
  std::ofstream(path("a.txt"), std::ios::binary) << std::string("one\0two\n", 8);
  EXPECT_EQ(morph::read_regular_file(path("a.txt"), "test file"), std::string("one\0two\n", 8));
  std::ofstream(path("empty.txt"), std::ios::binary);
  EXPECT_EQ(morph::read_regular_file(path("empty.txt"), "test file"), "");
}

TEST_F(FileIo, MissingFileIsAnIoErrorNamingIt) {
  const std::string m =
      error_of<morph::IoError>([&] { morph::read_regular_file(path("absent.nc"), "G-code file"); });
  EXPECT_TRUE(contains(m, "absent.nc")) << m;
  EXPECT_TRUE(contains(m, "No such file")) << m;
}

TEST_F(FileIo, FifoWithoutWriterIsRefusedAtOnce) {
  ASSERT_EQ(::mkfifo(path("pipe.nc").c_str(), 0600), 0);
  const auto start = std::chrono::steady_clock::now();
  const std::string m =
      error_of<morph::InputError>([&] { morph::read_regular_file(path("pipe.nc"), "G-code file"); });
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(2));
  EXPECT_TRUE(contains(m, "pipe.nc")) << m;
  EXPECT_TRUE(contains(m, "FIFO")) << m;
}

TEST_F(FileIo, DevicesAndDirectoriesAreRefusedByName) {
  fs::create_symlink("/dev/zero", path("zero.ply"));
  std::string m =
      error_of<morph::InputError>([&] { morph::read_regular_file(path("zero.ply"), "mesh file"); });
  EXPECT_TRUE(contains(m, "zero.ply")) << m;
  EXPECT_TRUE(contains(m, "character device")) << m;
  fs::create_directory(path("dir.json"));
  m = error_of<morph::InputError>([&] { morph::read_regular_file(path("dir.json"), "job file"); });
  EXPECT_TRUE(contains(m, "dir.json")) << m;
  EXPECT_TRUE(contains(m, "directory")) << m;
}

TEST_F(FileIo, SizeIsCheckedBeforeReading) {
  std::ofstream(path("big.nc"), std::ios::binary) << std::string(1000, 'x');
  const std::string m =
      error_of<morph::InputError>([&] { morph::read_regular_file(path("big.nc"), "G-code file", 999); });
  EXPECT_TRUE(contains(m, "big.nc")) << m;
  EXPECT_TRUE(contains(m, "over the limit")) << m;
  EXPECT_EQ(morph::read_regular_file(path("big.nc"), "G-code file", 1000).size(), 1000u);
}

TEST_F(FileIo, WriteReplacesTheFileThroughATemporaryOne) {
  std::ofstream(path("out.ply"), std::ios::binary) << "old";
  ::chmod(path("out.ply").c_str(), 0640);
  struct stat before {};
  ASSERT_EQ(::stat(path("out.ply").c_str(), &before), 0);
  morph::write_file_atomically(path("out.ply"), "new content");
  EXPECT_EQ(slurp("out.ply"), "new content");
  struct stat st {};
  ASSERT_EQ(::stat(path("out.ply").c_str(), &st), 0);
  EXPECT_NE(st.st_ino, before.st_ino);  // a new file renamed over the old one, never truncated in place
  EXPECT_EQ(st.st_mode & 0777, 0640u);
  // No temporary file is left behind.
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 1);
}

TEST_F(FileIo, WriteThroughASymlinkReplacesItsTarget) {
  fs::create_directory(path("real"));
  std::ofstream(path("real/result.ply")) << "old";
  fs::create_symlink("real/result.ply", path("link.ply"));
  morph::write_file_atomically(path("link.ply"), "new");
  EXPECT_TRUE(fs::is_symlink(path("link.ply")));
  EXPECT_EQ(slurp("real/result.ply"), "new");
}

TEST_F(FileIo, WriteFailuresNameTheFile) {
  const std::string missing = path("no_such_dir/x.ply");
  std::string m = error_of<morph::IoError>([&] { morph::write_file_atomically(missing, "x"); });
  EXPECT_TRUE(contains(m, missing)) << m;
  fs::create_directory(path("dir.ply"));
  m = error_of<morph::IoError>([&] { morph::write_file_atomically(path("dir.ply"), "x"); });
  EXPECT_TRUE(contains(m, "dir.ply")) << m;
  fs::create_symlink("loop_b.ply", path("loop_a.ply"));
  fs::create_symlink("loop_a.ply", path("loop_b.ply"));
  m = error_of<morph::IoError>([&] { morph::write_file_atomically(path("loop_a.ply"), "x"); });
  EXPECT_TRUE(contains(m, "loop_a.ply")) << m;
}

TEST_F(FileIo, WriteToAFullDeviceIsAnError) {
  if (::access("/dev/full", W_OK) != 0) GTEST_SKIP() << "no writable /dev/full here";
  fs::create_symlink("/dev/full", path("full.stl"));
  const std::string m =
      error_of<morph::IoError>([&] { morph::write_file_atomically(path("full.stl"), "bytes"); });
  EXPECT_TRUE(contains(m, "full.stl")) << m;
  EXPECT_TRUE(contains(m, "No space")) << m;
  EXPECT_TRUE(fs::is_symlink(path("full.stl")));  // the device is written into, not replaced
}

}  // namespace
