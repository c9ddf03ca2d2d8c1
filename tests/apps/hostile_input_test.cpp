// SPDX-License-Identifier: Apache-2.0
// The reproducers of ../shared/repro/hostile/ as regression tests, run through the morphmill
// binary as a user runs them: each hostile input ends in exit 2 with a message naming the file
// and the problem (or a correct result), never a signal, a hang or exit 3. The inputs are built
// here (the shared folder is not part of a clone); big ones at a size that runs in a second.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <tuple>
#include <vector>

#include "apps/command_support.h"

namespace {

namespace fs = std::filesystem;
const std::string kData = MORPHMILL_TEST_DATA;

const char* const kTetraPly =
    "ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty double y\nproperty double z\n"
    "element face 4\nproperty list uchar int vertex_indices\nend_header\n"
    "0 0 0\n10 0 0\n0 10 0\n0 0 10\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";

class HostileInput : public morphmill_test::ScratchDirTest {
 protected:
  struct Run {
    int exit_code = -1;  ///< -1: ended on a signal or did not finish within the limit
    std::string out, err;
  };
  /// Runs morphmill in the scratch directory, with stdin closed, under `timeout` and a 2 GiB
  /// address-space limit (so a runaway allocation fails fast instead of swapping).
  /// Under AddressSanitizer the limit is left out: its shadow memory alone reserves terabytes of
  /// address space (the sanitizer then reports any runaway allocation itself).
  Run morphmill(const std::string& arguments, int seconds = 20) const {
#if defined(__SANITIZE_ADDRESS__)
    const std::string limit;
    seconds *= 10;  // instrumented code runs several times slower
#else
    const std::string limit = "ulimit -v 2097152 && ";
#endif
    const std::string command = "cd '" + dir_.string() + "' && " + limit + "timeout -s KILL " +
                                std::to_string(seconds) + " '" + MORPHMILL_BINARY + "' " + arguments +
                                " < /dev/null > out.txt 2> err.txt";
    const int status = std::system(command.c_str());
    Run r;
    r.exit_code = WIFEXITED(status) && WEXITSTATUS(status) < 128 ? WEXITSTATUS(status) : -1;
    r.out = slurp("out.txt");
    r.err = slurp("err.txt");
    return r;
  }
  std::string slurp(const std::string& name) const {
    std::ifstream in(path(name), std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  }
  /// Exit 2, with `file` and every one of `words` on stderr.
  void expect_refusal(const Run& r, const std::string& file,
                      std::initializer_list<const char*> words = {}) const {
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find(file), std::string::npos) << r.err;
    for (const char* w : words)
      EXPECT_NE(r.err.find(w), std::string::npos) << "want '" << w << "': " << r.err;
  }
  std::string box_job(const std::string& gcode) const {
    return R"({"stock":{"type":"box","min":[0,0,0],"max":[100,60,20]},"tools":{"1":{"type":"ballend","radius":3,"length":40}},"paths":[{"tool":1,"gcode":")" +
           gcode + "\"}]}\n";
  }
  std::string mesh_job(const std::string& mesh) const {
    return R"({"stock":{"type":"mesh","path":")" + mesh +
           R"("},"tools":{"1":{"type":"sphere","radius":1}},"paths":[{"tool":1,"polyline":[[0,0,0],[1,1,1]]}]})";
  }
};

TEST_F(HostileInput, JsonNestedDeepIsRefusedWithItsPath) {
  write_text("deep.json", "{\"stock\": " + std::string(100000, '[') + std::string(100000, ']') + "}");
  expect_refusal(morphmill("info deep.json"), "deep.json", {"stock[0][0]", "nested deeper than 64"});
}

TEST_F(HostileInput, JsonNumberOverflowIsRefusedWithItsPath) {
  write_text("overflow.json", "{\"tolerance\": 1e400}");
  expect_refusal(morphmill("info overflow.json"), "overflow.json", {"tolerance", "number overflow"});
  write_text("overflow_deeper.json", "{\"paths\": [{}, {\"polyline\": [[0, 0, 33.1e308]]}]}");
  expect_refusal(morphmill("info overflow_deeper.json"), "overflow_deeper.json", {"paths[1].polyline[0][2]"});
  expect_refusal(morphmill("study overflow.json --out s"), "overflow.json", {"number overflow"});
}

TEST_F(HostileInput, ObjFaceWithoutVertexIndexIsRefused) {
  write_text("slash.obj", "f /1");
  expect_refusal(morphmill("mesh-info slash.obj"), "slash.obj", {"line 1", "no valid vertex index"});
  write_text("job.json", mesh_job("slash.obj"));
  expect_refusal(morphmill("info job.json"), "slash.obj");
}

TEST_F(HostileInput, ObjMaterialLibrariesAreNeverOpened) {
  ASSERT_EQ(::mkfifo(path("materials.mtl").c_str(), 0600), 0);
  for (const char* library : {"/dev/zero", "materials.mtl"}) {
    SCOPED_TRACE(library);
    write_text("tetra.obj",
               std::string("mtllib ") + library +
                   "\nv 0 0 0\nv 10 0 0\nv 0 10 0\nv 0 0 10\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
    const Run r = morphmill("mesh-info tetra.obj --json", 10);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("\"triangles\": 4"), std::string::npos) << r.out;
  }
}

TEST_F(HostileInput, PlyTagsOutsideInt32AreRefused) {
  write_text(
      "source.ply",
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\n"
      "element face 1\nproperty list uchar int vertex_indices\nproperty double source\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n3 0 1 2 1e10\n");
  expect_refusal(morphmill("mesh-info source.ply"), "source.ply", {"source", "not a 32-bit integer"});
}

TEST_F(HostileInput, PlyNanVertexIndexIsRefused) {
  // The PLY fuzzer's find: float vertex indices holding NaN passed both range comparisons and
  // were cast to an integer (UBSan: -nan is outside the range of unsigned int).
  write_text(
      "nan.ply",
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\n"
      "element face 1\nproperty list uchar float vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 "
      "nan\n");
  expect_refusal(morphmill("mesh-info nan.ply"), "nan.ply", {"refers to vertex nan"});
}

TEST_F(HostileInput, PlyCountsBeyondTheBytesAreRefusedBeforeAllocating) {
  write_text("huge.ply",
             "ply\nformat binary_little_endian 1.0\nelement vertex 1099511627776\nproperty float x\n"
             "property float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\n"
             "end_header\n");
  expect_refusal(morphmill("mesh-info huge.ply"), "huge.ply", {"1099511627776", "bytes"});
  write_text("faces.ply",
             std::string(kTetraPly).replace(std::string(kTetraPly).find("face 4"), 6, "face 1099511627776"));
  expect_refusal(morphmill("mesh-info faces.ply"), "faces.ply",
                 {"'face' records", "bytes follow the header"});
}

TEST_F(HostileInput, SpecialFilesAreRefusedByName) {
  ASSERT_EQ(::mkfifo(path("fifo.nc").c_str(), 0600), 0);
  fs::create_symlink("/dev/zero", path("zero.nc"));
  fs::create_symlink("/dev/zero", path("zero.stl"));
  fs::create_symlink("/dev/zero", path("zero.json"));
  fs::create_directory(path("dir.stl"));
  fs::create_directory(path("dir.json"));
  write_text("fifo.json", box_job("fifo.nc"));
  write_text("zero_gcode.json", box_job("zero.nc"));
  write_text("zero_stock.json", mesh_job("zero.stl"));
  expect_refusal(morphmill("info fifo.json", 10), "fifo.nc", {"FIFO"});
  expect_refusal(morphmill("erode fifo.json -o out.ply", 10), "fifo.nc", {"FIFO"});
  expect_refusal(morphmill("info zero_gcode.json", 10), "zero.nc", {"character device"});
  expect_refusal(morphmill("info zero_stock.json", 10), "zero.stl", {"character device"});
  expect_refusal(morphmill("mesh-info zero.stl", 10), "zero.stl", {"character device"});
  expect_refusal(morphmill("info zero.json", 10), "zero.json", {"character device"});
  expect_refusal(morphmill("mesh-info dir.stl", 10), "dir.stl", {"directory"});
  expect_refusal(morphmill("info dir.json", 10), "dir.json", {"directory"});
}

TEST_F(HostileInput, BlankLinesReserveNoMoves) {
  // gen_gcode_big.py blank at 8 MB: one reserved Move (136 bytes) per newline would be 1.1 GB,
  // past this test's address-space limit once the binary's own mappings are counted.
  write_text("blank.nc", std::string(8 << 20, '\n'));
  write_text("blank.json", box_job("blank.nc"));
  const Run r = morphmill("info blank.json --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("\"total\": 0"), std::string::npos) << r.out;
}

TEST_F(HostileInput, AVeryLongLineIsReadAndItsErrorsDoNotRepeatIt) {
  // gen_gcode_big.py oneline at 4 MB: "G1 X1 (" + 4 MB + ")" on line 3. Its program sets no feed
  // rate, which LinuxCNC refuses (issue 20): MorphMill reads the path and warns, naming the file
  // and the line without repeating the 4 MB line; --strict refuses it.
  const std::string program = "G21 G90 G17\nG0 X0 Y0 Z25\nG1 X1 (" + std::string(4 << 20, 'x') + ")\nG1 X2\n";
  write_text("oneline.nc", program);
  write_text("oneline.json", box_job("oneline.nc"));
  const Run warned = morphmill("info oneline.json --json");
  ASSERT_EQ(warned.exit_code, 0) << warned.err.substr(0, 2000);
  const nlohmann::json summary = nlohmann::json::parse(warned.out);
  EXPECT_EQ(summary["moves"]["by_kind"]["linear"], 2);
  ASSERT_EQ(summary["warnings"].size(), 1u);
  EXPECT_EQ(summary["warnings"][0]["file"], "oneline.nc");
  EXPECT_EQ(summary["warnings"][0]["line"], 3);
  const std::string message = summary["warnings"][0]["message"];
  EXPECT_NE(message.find("G1 with no feed rate"), std::string::npos) << message;
  EXPECT_LT(message.size(), 1000u);
  const Run refused = morphmill("info oneline.json --strict");
  expect_refusal(refused, "oneline.json", {"refused under --strict"});
  EXPECT_NE(refused.out.find("oneline.nc:3: G1 with no feed rate"), std::string::npos);
  EXPECT_LT(refused.out.size() + refused.err.size(), 10000u);  // the 4 MB line is not repeated
  // With a feed rate the same line makes its move, with no warning: 2 linear moves up to (2, 0, 25).
  write_text("oneline_feed.nc", "F600\n" + program);
  write_text("oneline_feed.json", box_job("oneline_feed.nc"));
  const Run read = morphmill("info oneline_feed.json --json");
  ASSERT_EQ(read.exit_code, 0) << read.err;
  const nlohmann::json info = nlohmann::json::parse(read.out);
  EXPECT_EQ(info["moves"]["by_kind"]["linear"], 2);
  EXPECT_EQ(info["bounds"]["max"], nlohmann::json::parse("[2, 0, 25]"));
}

TEST_F(HostileInput, UnwritableOutputsAreExit2NamingThemEveryTime) {
  // The write fails while the summary's parallel topology report runs: 10 runs each, as the
  // SIGSEGV of the unwinding task group came in a fraction of runs.
  fs::create_directory(path("dir.ply"));
  fs::create_symlink("loop_b.ply", path("loop_a.ply"));
  fs::create_symlink("loop_a.ply", path("loop_b.ply"));
  for (const char* out : {"/nonexistent/x.ply", "dir.ply", "loop_a.ply"}) {
    SCOPED_TRACE(out);
    for (int run = 0; run < 10; ++run) {
      const Run r = morphmill("erode '" + kData + "/jobs/single_slot.json' -o " + out);
      ASSERT_EQ(r.exit_code, 2) << r.err;
      ASSERT_NE(r.err.find(fs::path(out).filename().string()), std::string::npos) << r.err;
    }
  }
}

TEST_F(HostileInput, FullDeviceOutputIsAnError) {
  if (::access("/dev/full", W_OK) != 0) GTEST_SKIP() << "no writable /dev/full here";
  for (const char* out : {"full.stl", "full.ply"}) {
    SCOPED_TRACE(out);
    fs::create_symlink("/dev/full", path(out));
    expect_refusal(morphmill("erode '" + kData + "/jobs/single_slot.json' -o " + out), out, {"No space"});
  }
}

TEST_F(HostileInput, AFailedWriteLeavesTheOldResult) {
  // A result is the old file or the new one: here the new one cannot be written (the directory
  // is made read-only), so the old bytes must still be there, whole.
  if (::geteuid() == 0) GTEST_SKIP() << "root writes into read-only directories";
  fs::create_directory(path("w"));
  write_text("w/result.ply", kTetraPly);
  ::chmod(path("w").c_str(), 0555);
  const Run r = morphmill("erode '" + kData + "/jobs/single_slot.json' -o w/result.ply");
  ::chmod(path("w").c_str(), 0755);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(slurp("w/result.ply"), kTetraPly);
}

/// A closed cube [lo, lo + size]^3 as PLY vertex and face lines, its vertices numbered from `first`.
std::string cube_lines(double lo, double size, int first, std::string& faces) {
  std::string vertices;
  for (int k = 0; k < 8; ++k)
    vertices += std::to_string(lo + size * (k & 1)) + " " + std::to_string(lo + size * (k >> 1 & 1)) + " " +
                std::to_string(lo + size * (k >> 2 & 1)) + "\n";
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads)
    faces += "4 " + std::to_string(first + q[0]) + " " + std::to_string(first + q[1]) + " " +
             std::to_string(first + q[2]) + " " + std::to_string(first + q[3]) + "\n";
  return vertices;
}

std::string two_cubes_ply(double second_lo, double second_size) {
  std::string faces;
  const std::string vertices = cube_lines(0, 10, 0, faces) + cube_lines(second_lo, second_size, 8, faces);
  return "ply\nformat ascii 1.0\nelement vertex 16\nproperty double x\nproperty double y\nproperty double z\n"
         "element face 12\nproperty list uchar int vertex_indices\nend_header\n" +
         vertices + faces;
}

TEST_F(HostileInput, NestedOrOverlappingStockShellsAreRefused) {
  for (const auto& [name, lo, size] :
       {std::tuple<const char*, double, double>{"overlap.ply", 5, 10}, {"nested.ply", 2, 6}}) {
    SCOPED_TRACE(name);
    write_text(name, two_cubes_ply(lo, size));
    write_text("job.json", mesh_job(name));
    expect_refusal(morphmill("info job.json"), name, {"shells", "triangle"});
  }
  // Two cubes apart are two pieces of stock, as before.
  write_text("apart.ply", two_cubes_ply(20, 5));
  write_text("job.json", mesh_job("apart.ply"));
  EXPECT_EQ(morphmill("info job.json").exit_code, 0);
}

TEST_F(HostileInput, ToleranceBelowTheCoordinatesResolutionIsRefused) {
  write_text(
      "far.json",
      R"({"stock":{"type":"box","min":[1e15,0,0],"max":[1.0000000000001e15,60,20]},"tools":{"1":{"type":"ballend","radius":3,"length":40}},"paths":[{"tool":1,"polyline":[[999999999999995,30,17],[1000000000000105,30,17]]}],"tolerance":0.01})");
  expect_refusal(morphmill("erode far.json -o out.ply"), "far.json", {"resolve", "1e+15"});
}

TEST_F(HostileInput, AThousandTurnArcHasItsBoundsAtATinyTolerance) {
  // info_arc_bounds_wrong.json: the chord count overflowed int and the box missed the arc.
  write_text("arc.nc", "G21 G90 G17\nG0 X0 Y0 Z25\nG1 Z15 F300\nG1 X10\nG3 X10 Y0 I-10 J0 P1000\n");
  write_text(
      "arc.json",
      R"({"stock":{"type":"box","min":[-20,-20,0],"max":[20,20,20]},"tools":{"1":{"type":"sphere","radius":2}},"paths":[{"tool":1,"gcode":"arc.nc"}],"tolerance":1e-12})");
  const Run r = morphmill("info arc.json --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  const std::vector<double> lo = j["bounds"]["min"], hi = j["bounds"]["max"];
  const std::vector<double> want_lo{-10, -10, 15}, want_hi{10, 10, 25};
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(lo[k], want_lo[k], 1e-4);
    EXPECT_NEAR(hi[k], want_hi[k], 1e-4);
  }
}

TEST_F(HostileInput, EveryCommandSaysTheJobsWarningsAndStrictRefusesThem) {
  const std::string job = "'" + kData + "/jobs/single_slot.json'";
  std::ifstream in(kData + "/jobs/single_slot.json");
  std::string text(std::istreambuf_iterator<char>(in), {});
  text.insert(text.find('{') + 1, "\"tolerence\": 0.05, ");
  write_text("misspelt.json", text);
  const Run erode = morphmill("erode misspelt.json -o out.ply");
  EXPECT_EQ(erode.exit_code, 0) << erode.err;
  EXPECT_NE(erode.err.find("tolerence"), std::string::npos) << erode.err;
  const Run reference = morphmill("reference misspelt.json --voxel 1 -o ref.ply");
  EXPECT_EQ(reference.exit_code, 0) << reference.err;
  EXPECT_NE(reference.err.find("tolerence"), std::string::npos) << reference.err;
  expect_refusal(morphmill("erode misspelt.json -o strict.ply --strict"), "misspelt.json", {"--strict"});
  expect_refusal(morphmill("--strict info misspelt.json"), "misspelt.json", {"--strict"});
  EXPECT_EQ(morphmill("erode " + job + " -o clean.ply --strict").exit_code, 0);
}

TEST_F(HostileInput, DeviationCountsAndDistancesAreRangeChecked) {
  write_text("a.ply", kTetraPly);
  write_text("b.ply", kTetraPly);
  for (const char* option : {"--max-distance -1", "--max-distance 0"})
    expect_refusal(morphmill(std::string("deviation a.ply b.ply --ray ") + option), "--max-distance");
  for (const char* option :
       {"--samples -5", "--samples 200000000", "--samples 4294967295", "--edge-samples -1"})
    expect_refusal(morphmill(std::string("deviation a.ply b.ply ") + option), "samples");
}

TEST_F(HostileInput, AnInfiniteMemoryCapIsAFiniteOne) {
  const Run r = morphmill("reference '" + kData +
                          "/jobs/through_slots.json' --voxel 0.001 --memory-cap inf -o ref.ply");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(r.err.find("cap of 0 MiB"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("MiB"), std::string::npos) << r.err;
}

}  // namespace
