// SPDX-License-Identifier: Apache-2.0
// deviation's up-front memory estimate against the measured peak (the child's ru_maxrss) of the
// morphmill binary, on two tori of 320k and 80k triangles with the options that change what is
// held (one or two sides, many samples, per-vertex values, a picture): within a factor of 2 either
// way. And the refusal: a --memory-cap below the estimate stops before anything is indexed.
#include <gtest/gtest.h>
#include <morphmill/mesh_io.h>

#include <string>

#include "apps/command_support.h"
#include "common/test_meshes.h"

namespace {

using morphmill_test::estimated_mib;
using morphmill_test::Measured;
using morphmill_test::run_measured;

class DeviationEstimate : public morphmill_test::ScratchDirTest {
 protected:
  void SetUp() override {
    morphmill_test::ScratchDirTest::SetUp();
    morphmill::write_mesh(morphmill_test::torus(30.0, 10.0, 800, 200), path("a.ply"));  // 320k triangles
    morphmill::write_mesh(morphmill_test::torus(30.0, 10.1, 400, 100), path("b.ply"));  // 80k triangles
  }
};

TEST_F(DeviationEstimate, IsWithinAFactorOfTwoOfTheMeasuredPeak) {
  if (!morphmill_test::kPeakMemoryIsTheProgramsOwn) GTEST_SKIP() << "peak memory under AddressSanitizer";
  for (const std::string options : {"", " --one-sided", " --samples 1000000", " --no-vertices --samples 10",
                                    " --heatmap h.ply", " --png p.png --size 1600x1200"}) {
    const Measured m = run_measured("deviation a.ply b.ply" + options, dir_);
    ASSERT_EQ(m.exit_code, 0) << options << ": " << m.err;
    const double estimate = estimated_mib(m.out) * double(1 << 20);
    ASSERT_GT(estimate, 0.0) << options << ": " << m.out;
    EXPECT_LE(estimate, 2.0 * m.peak_bytes) << options << ": estimate " << estimate / (1 << 20)
                                            << " MiB, peak " << m.peak_bytes / (1 << 20) << " MiB";
    EXPECT_GE(estimate, 0.5 * m.peak_bytes) << options << ": estimate " << estimate / (1 << 20)
                                            << " MiB, peak " << m.peak_bytes / (1 << 20) << " MiB";
  }
}

TEST_F(DeviationEstimate, ACapBelowTheEstimateRefusesBeforeIndexing) {
  const Measured m =
      run_measured("deviation a.ply b.ply --samples 2000000 --heatmap h.ply --memory-cap 0.15", dir_);
  EXPECT_EQ(m.exit_code, 2) << m.err;
  for (const char* expected : {"a.ply", "b.ply", "over the memory cap", "--samples", "--one-sided"})
    EXPECT_NE(m.err.find(expected), std::string::npos) << expected << " not in: " << m.err;
  EXPECT_FALSE(std::filesystem::exists(path("h.ply")));
  // The meshes were read (about 30 MB), nothing indexed or sampled (the estimate is over 400 MB).
  if (morphmill_test::kPeakMemoryIsTheProgramsOwn) {
    EXPECT_LT(m.peak_bytes, 150.0 * (1 << 20));
  }
}

}  // namespace
