// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file convex_minimum.h
/// The pieces every exact tool-sweep distance is built from (the generator's, the reference's):
/// a golden-section minimum of a convex function and the exact capped-cylinder distance.
#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace morph::detail {

/// The bracket of a golden-section search: lo < x1 < x2 < hi with f's values (f_lo, f_hi are
/// NaN while that end has not been evaluated).
struct GoldenBracket {
  double lo, f_lo, x1, f1, x2, f2, hi, f_hi;
};

/// (argument, value) of the minimum of a convex (or, on a small piece, unimodal) function over
/// [lo, hi] by golden section, to 1e-14 in the argument; the ends are candidates too. Before each
/// step `stop(bracket, &value)` may end the search early: it returns true and sets the value to
/// report (the argument is then NaN).
template <class F, class Stop>
std::pair<double, double> golden_minimum(F&& f, double lo, double hi, Stop&& stop) {
  constexpr double kInvPhi = 0.6180339887498949;
  const double unknown = std::numeric_limits<double>::quiet_NaN();
  double f_lo = unknown, f_hi = unknown;
  double x1 = hi - kInvPhi * (hi - lo), x2 = lo + kInvPhi * (hi - lo);
  double f1 = f(x1), f2 = f(x2);
  for (int i = 0; i < 64 && hi - lo > 1e-14; ++i) {
    double value = 0.0;
    if (stop(GoldenBracket{lo, f_lo, x1, f1, x2, f2, hi, f_hi}, &value)) return {unknown, value};
    if (f1 < f2) {
      hi = x2;
      f_hi = f2;
      x2 = x1;
      f2 = f1;
      x1 = hi - kInvPhi * (hi - lo);
      f1 = f(x1);
    } else {
      lo = x1;
      f_lo = f1;
      x1 = x2;
      f1 = f2;
      x2 = lo + kInvPhi * (hi - lo);
      f2 = f(x2);
    }
  }
  std::pair<double, double> best{f1 < f2 ? x1 : x2, std::min(f1, f2)};
  for (double t : {lo, hi}) {
    const double v = f(t);
    if (v < best.second) best = {t, v};
  }
  return best;
}

template <class F>
std::pair<double, double> golden_minimum(F&& f, double lo, double hi) {
  return golden_minimum(std::forward<F>(f), lo, hi, [](const GoldenBracket&, double*) { return false; });
}

/// Exact signed distance to a vertical capped cylinder of radius r around the z axis between
/// heights z0 and z1, with q relative to that axis.
/// (Square roots rather than std::hypot: no over- or underflow at machining scales, and this is
/// the body search's inner loop.)
inline double capped_cylinder_distance(const Eigen::Vector3d& q, double r, double z0, double z1) {
  const double dr = std::sqrt(q.x() * q.x() + q.y() * q.y()) - r;
  const double dz = std::max(z0 - q.z(), q.z() - z1);
  const double out_r = std::max(dr, 0.0), out_z = std::max(dz, 0.0);
  return std::sqrt(out_r * out_r + out_z * out_z) + std::min(std::max(dr, dz), 0.0);
}

}  // namespace morph::detail
