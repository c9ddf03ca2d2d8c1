// SPDX-License-Identifier: Apache-2.0
#include <morph/facet_clipping.h>
#include <morph/quantize.h>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include <cmath>
#include <random>

namespace {

using Eigen::Vector3d;
using morph::ExactPlane;

Vector3d random_unit(std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  return Vector3d(g(rng), g(rng), g(rng)).normalized();
}

// The float look decides only what the exact predicate decides alike: for planes at every
// distance from a corner (down to exactly through it), for well- and ill-conditioned corners,
// look_side() is 0 or side_at_vertex()'s sign; and it does decide the planes clearly apart.
TEST(CornerLook, LookSideIsSideAtVertexWhereverItAnswers) {
  std::mt19937_64 rng(29);
  std::uniform_real_distribution<double> coord(-80, 80), unit(0, 1);
  int answered = 0, asked = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const Vector3d corner(coord(rng), coord(rng), coord(rng));
    // Two thirds of the corners have a third normal close to the plane of the first two (as a
    // tool facet, its neighbour and the silhouette plane of their edge).
    const Vector3d n0 = random_unit(rng), n1 = random_unit(rng);
    Vector3d n2 = random_unit(rng);
    if (trial % 3 != 0)
      n2 = (n0.cross(n1).normalized() * std::pow(10.0, -8.0 * unit(rng)) + (n0 + n1).normalized())
               .normalized();
    const ExactPlane s{n0, n0.dot(corner), 1, 1}, a{n1, n1.dot(corner), 2, -1}, b{n2, n2.dot(corner), 3, 1};
    const std::optional<morph::CornerLook> look = morph::corner_look(s, a, b);
    if (!look) continue;
    for (int k = 0; k < 8; ++k) {
      const Vector3d n = random_unit(rng);
      // 0 (through the corner, as far as a double tells) up to 10 job units away.
      const double distance = k == 0 ? 0.0 : std::pow(10.0, -15.0 + 16.0 * unit(rng)) * (k % 2 ? 1 : -1);
      const ExactPlane d{n, n.dot(corner) + distance, 4 + static_cast<std::uint64_t>(k % 2), k % 3 ? 1 : -1};
      const int quick = morph::look_side(*look, d, d.normal.norm());
      ++asked;
      if (quick == 0) continue;
      ++answered;
      ASSERT_EQ(quick, morph::side_at_vertex(s, a, b, d))
          << "trial " << trial << ", plane " << k << " at " << distance << " from the corner";
    }
  }
  // Planes more than a few 1e-9 of the coordinates away are decided by the look.
  EXPECT_GT(answered, asked / 3);
}

}  // namespace
