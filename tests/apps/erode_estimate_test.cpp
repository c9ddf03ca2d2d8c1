// SPDX-License-Identifier: Apache-2.0
// erode's up-front memory estimate against the measured peak (the child's ru_maxrss) of the
// morphmill binary on the bundled jobs: within a factor of 2 either way. And the refusals the
// estimate makes: --memory-cap below it, and the hostile reproducers that used to run out of
// memory (tolerance 1e-6, a P1000000 circle).
#include <gtest/gtest.h>
#include <morphmill/mesh_io.h>

#include <fstream>
#include <string>

#include "apps/command_support.h"
#include "common/test_meshes.h"

namespace {

using morphmill_test::estimated_mib;
using morphmill_test::Measured;
using morphmill_test::run_measured;

const std::string kData = MORPHMILL_TEST_DATA;

void expect_estimate_within_two_of_the_peak(const std::string& job, const std::string& options) {
  if (!morphmill_test::kPeakMemoryIsTheProgramsOwn) GTEST_SKIP() << "peak memory under AddressSanitizer";
  const auto dir = morphmill_test::scratch_dir("erode_estimate", job + options);
  const Measured m = run_measured("erode '" + kData + "/jobs/" + job + ".json' -o '" +
                                      (dir / "out.ply").string() + "' --allow-open" + options,
                                  dir);
  // 1 would be a surface that is not a sound solid (written with --allow-open): the run is whole
  // either way, and so is its peak.
  ASSERT_TRUE(m.exit_code == 0 || m.exit_code == 1) << m.err;
  const double estimate = estimated_mib(m.out) * double(1 << 20);
  ASSERT_GT(estimate, 0.0) << m.out;
  EXPECT_LE(estimate, 2.0 * m.peak_bytes)
      << "estimate " << estimate / (1 << 20) << " MiB, peak " << m.peak_bytes / (1 << 20) << " MiB";
  EXPECT_GE(estimate, 0.5 * m.peak_bytes)
      << "estimate " << estimate / (1 << 20) << " MiB, peak " << m.peak_bytes / (1 << 20) << " MiB";
  std::filesystem::remove_all(dir);
}

// The estimate (the sweeps' facets, generator/erode_limits.cpp), on the bundled jobs.
class ErodeEstimate : public ::testing::TestWithParam<const char*> {};

TEST_P(ErodeEstimate, IsWithinAFactorOfTwoOfTheMeasuredPeak) {
  expect_estimate_within_two_of_the_peak(GetParam(), "");
}

INSTANTIATE_TEST_SUITE_P(BundledJobs, ErodeEstimate,
                         ::testing::Values("single_slot", "helix_pocket", "leave_reenter", "slots",
                                           "through_slots", "design_gouge_excess", "mesh_stock"));

class ErodeRefusal : public morphmill_test::ScratchDirTest {};

TEST_F(ErodeRefusal, Generator2RefusesATinyToleranceBeforeBuildingAnything) {
  const auto r = run_measured(
      "erode '" + kData + "/jobs/slots.json' --tolerance 1e-6 -o '" + path("out.ply") + "' --memory-cap 8",
      dir_);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("slots.json: erode: at tolerance 1e-06"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("sweep facets"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("over the memory cap"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(path("out.ply")));
  if (morphmill_test::kPeakMemoryIsTheProgramsOwn) {
    EXPECT_LT(r.peak_bytes, 200.0 * (1 << 20));
  }
}

TEST_F(ErodeRefusal, ACapBelowTheEstimateRefusesBeforeComputing) {
  const auto r = run_measured(
      "erode '" + kData + "/jobs/slots.json' -o '" + path("out.ply") + "' --memory-cap 0.01", dir_);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("slots.json"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("over the memory cap"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("raise the tolerance"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(path("out.ply")));
  if (morphmill_test::kPeakMemoryIsTheProgramsOwn) {
    EXPECT_LT(r.peak_bytes, 200.0 * (1 << 20));
  }
}

TEST_F(ErodeRefusal, ATinyToleranceIsRefusedByTheEstimate) {
  // erode_tol_1e-6.json of the hostile reproducers: the kernel's OOM killer stopped it at 21.7 GB.
  const auto r = run_measured(
      "erode '" + kData + "/jobs/slots.json' --tolerance 1e-6 -o '" + path("out.ply") + "' --memory-cap 8",
      dir_);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("slots.json"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("MiB"), std::string::npos) << r.err;
  if (morphmill_test::kPeakMemoryIsTheProgramsOwn) {
    EXPECT_LT(r.peak_bytes, 500.0 * (1 << 20));
  }
}

TEST_F(ErodeRefusal, VerifyAndCompareRefuseATinyToleranceBeforeTheGeneratorRuns) {
  // The same estimate guards the generator inside verify and compare (and study and stress).
  for (const std::string& command :
       {"verify '" + kData + "/jobs/slots.json' -o out --tolerance 1e-6 --memory-cap 8",
        "compare '" + kData + "/jobs/design_gouge_excess.json' --tolerance 1e-6 --memory-cap 8"}) {
    const auto r = run_measured(command, dir_);
    EXPECT_EQ(r.exit_code, 2) << command << ": " << r.err;
    EXPECT_NE(r.err.find(".json: erode: at tolerance 1e-06"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("over the memory cap"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("--memory-cap 8192 MiB"), std::string::npos) << r.err;
    if (morphmill_test::kPeakMemoryIsTheProgramsOwn) {
      EXPECT_LT(r.peak_bytes, 500.0 * (1 << 20)) << command;
    }
  }
}

TEST_F(ErodeRefusal, ALargeMeshStockIsRefusedBeforeItsStructuresAreBuilt) {
  // sphere_5m_erode of the hostile reproducers, a 25th of the size: the stock's own structures and
  // patches (1.4 KB a triangle) used to be built before the estimate, and ran out of memory.
  morphmill::write_mesh(morphmill_test::torus(30.0, 10.0, 500, 200), path("torus.ply"));
  write_text(
      "torus.json",
      R"({"stock":{"type":"mesh","path":"torus.ply"},"tools":{"1":{"type":"ballend","radius":3,"length":40}},"paths":[{"tool":1,"polyline":[[-45,0,5],[45,0,5]]}]})");
  const auto r = run_measured("erode torus.json -o out.ply --memory-cap 0.2", dir_);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("torus.json"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("200000 stock triangles"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("over the memory cap"), std::string::npos) << r.err;
  if (morphmill_test::kPeakMemoryIsTheProgramsOwn) {
    EXPECT_LT(r.peak_bytes, 150.0 * (1 << 20));
  }
}

TEST_F(ErodeRefusal, AMillionTurnCircleIsRefused) {
  // erode_arc_p1e6.json: one G3 P1000000 full circle (std::bad_alloc after 57 s before).
  write_text("circle.nc", "G21 G90 G17\nG0 X10 Y0 Z20\nG3 X10 Y0 I-10 J0 P1000000 F300\n");
  write_text(
      "circle.json",
      R"({"stock":{"type":"box","min":[-20,-20,0],"max":[20,20,20]},"tools":{"1":{"type":"ballend","radius":3,"length":40}},"paths":[{"tool":1,"gcode":"circle.nc"}]})");
  const auto r = run_measured("erode circle.json -o out.ply --memory-cap 8", dir_);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("circle"), std::string::npos) << r.err;
}

}  // namespace
