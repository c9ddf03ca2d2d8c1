// SPDX-License-Identifier: Apache-2.0
#include <morph/planar_deviation.h>

#include <cmath>
#include <limits>

#include "planar/planar_index.h"

namespace morph::planar {

namespace {

double signed_distance(const RegionIndex& other, const Vec2& p) {
  const double d = other.nearest(p).distance;
  if (d == 0.0 || !std::isfinite(d)) return d;
  return other.contains(p) ? -d : d;
}

/// Samples of one curve: every `spacing`, plus the refined largest |distance|.
std::vector<DeviationSample> measure_curve(const Curve& c, const RegionIndex& other, double spacing) {
  const int n = std::max(4, static_cast<int>(std::ceil(length(c) / spacing)));
  std::vector<DeviationSample> samples(static_cast<std::size_t>(n) + 1);
  int best = 0;
  for (int i = 0; i <= n; ++i) {
    const double t = static_cast<double>(i) / n;
    samples[i].point = point_at(c, t);
    samples[i].distance = signed_distance(other, samples[i].point);
    samples[i].from = c.from;
    if (std::abs(samples[i].distance) > std::abs(samples[best].distance)) best = i;
  }
  if (!std::isfinite(samples[best].distance)) return samples;
  // Golden-section search for the largest |distance| between the best sample's neighbours.
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  double lo = std::max(0, best - 1) / static_cast<double>(n),
         hi = std::min(n, best + 1) / static_cast<double>(n);
  auto f = [&](double t) { return std::abs(signed_distance(other, point_at(c, t))); };
  double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo), f1 = f(x1), f2 = f(x2);
  for (int k = 0; k < 60 && hi - lo > 1e-15; ++k) {
    if (f1 > f2) {
      hi = x2;
      x2 = x1;
      f2 = f1;
      x1 = hi - g * (hi - lo);
      f1 = f(x1);
    } else {
      lo = x1;
      x1 = x2;
      f1 = f2;
      x2 = lo + g * (hi - lo);
      f2 = f(x2);
    }
  }
  const double t = f1 > f2 ? x1 : x2;
  DeviationSample refined{point_at(c, t), signed_distance(other, point_at(c, t)), c.from};
  if (std::abs(refined.distance) > std::abs(samples[best].distance)) samples.push_back(refined);
  return samples;
}

DirectedDeviation measure(const Region& from, const RegionIndex& to, double spacing, ExecutionPolicy policy) {
  std::vector<const Curve*> curves;
  for (const Loop& loop : from.loops)
    for (const Curve& c : loop.curves) curves.push_back(&c);
  std::vector<std::vector<DeviationSample>> per_curve(curves.size());
  for_each_index(policy, 0, curves.size(),
                 [&](std::size_t i) { per_curve[i] = measure_curve(*curves[i], to, spacing); });
  DirectedDeviation out;
  double weighted = 0.0, total = 0.0;
  for (std::size_t i = 0; i < curves.size(); ++i) {
    const std::vector<DeviationSample>& samples = per_curve[i];
    const double len = length(*curves[i]);
    double sum = 0.0;
    for (const DeviationSample& s : samples) {
      if (s.distance > out.max_outside) out.max_outside = s.distance;
      if (-s.distance > out.max_inside) out.max_inside = -s.distance;
      if (std::abs(s.distance) >= std::abs(out.worst.distance)) out.worst = s;
      sum += std::abs(s.distance);
    }
    weighted += len * sum / static_cast<double>(samples.size());
    total += len;
    out.samples.insert(out.samples.end(), samples.begin(), samples.end());
  }
  out.mean_abs = total > 0.0 ? weighted / total : 0.0;
  return out;
}

}  // namespace

PlanarDeviation planar_deviation(const Region& a, const Region& b, const DeviationOptions& options) {
  PlanarDeviation result;
  Box2 extent = bounds(a);
  extent.extend(bounds(b));
  const double spacing =
      options.spacing > 0.0 ? options.spacing : (extent.isEmpty() ? 1.0 : extent.sizes().maxCoeff() / 2000.0);
  const RegionIndex index_a(a), index_b(b);
  result.a_to_b = measure(a, index_b, spacing, options.policy);
  result.b_to_a = measure(b, index_a, spacing, options.policy);
  return result;
}

}  // namespace morph::planar
