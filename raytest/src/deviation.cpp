// SPDX-License-Identifier: Apache-2.0
#include <morph/exceptions.h>
#include <raytest/deviation.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <tuple>

namespace raytest {

double percentile_of_sorted(const std::vector<double>& sorted, double q) {
  if (sorted.empty()) return 0.0;
  const double h = (static_cast<double>(sorted.size()) - 1.0) * std::clamp(q, 0.0, 100.0) / 100.0;
  const auto below = static_cast<std::size_t>(std::floor(h));
  const std::size_t above = std::min(below + 1, sorted.size() - 1);
  return sorted[below] + (h - static_cast<double>(below)) * (sorted[above] - sorted[below]);
}

DeviationClass classify(double value, const ToleranceBand& band) {
  if (value < band.low) return DeviationClass::Gouge;
  if (value > band.high) return DeviationClass::Excess;
  return DeviationClass::Within;
}

const char* to_string(DeviationClass kind) {
  switch (kind) {
    case DeviationClass::Gouge:
      return "gouge";
    case DeviationClass::Within:
      return "within";
    case DeviationClass::Excess:
      return "excess";
  }
  return "?";
}

namespace {

// Edges k * band.low .. 0 .. k * band.high; values beyond the outer edges are under/overflow.
Histogram band_histogram(const std::vector<double>& sorted, const ToleranceBand& band, std::size_t per_side) {
  Histogram h;
  for (std::size_t k = band.low < 0 ? per_side : 0; k >= 1; --k)
    h.edges.push_back(band.low * static_cast<double>(k));
  h.edges.push_back(0.0);
  for (std::size_t k = 1; band.high > 0 && k <= per_side; ++k)
    h.edges.push_back(band.high * static_cast<double>(k));
  if (h.edges.size() < 2) return {};
  h.counts.assign(h.edges.size() - 1, 0);
  for (double v : sorted) {
    if (v < h.edges.front()) {
      ++h.underflow;
    } else if (v > h.edges.back()) {
      ++h.overflow;
    } else {
      const auto above = std::upper_bound(h.edges.begin(), h.edges.end(), v) - h.edges.begin();
      const std::size_t bin = std::min<std::size_t>(static_cast<std::size_t>(above) - 1, h.counts.size() - 1);
      ++h.counts[bin];
    }
  }
  return h;
}

}  // namespace

DeviationStats compute_stats(std::vector<double> values, const StatsOptions& options) {
  DeviationStats stats;
  stats.tolerance = options.tolerance;
  stats.band = options.band.empty() ? ToleranceBand{-options.tolerance, options.tolerance} : options.band;
  if (stats.band.low > 0 || stats.band.high < 0 || std::isnan(stats.band.low) || std::isnan(stats.band.high))
    throw morph::InputError("tolerance band must satisfy low <= 0 <= high");
  const auto finite_end =
      std::partition(values.begin(), values.end(), [](double v) { return !std::isnan(v); });
  stats.misses = static_cast<std::size_t>(values.end() - finite_end);
  values.erase(finite_end, values.end());
  stats.count = values.size();
  if (values.empty()) return stats;
  // Sorting first makes every sum independent of the order the values were produced in (and of
  // the threads: a sort's result is one sequence whatever the algorithm).
  tbb::parallel_sort(values.begin(), values.end());
  stats.min = values.front();
  stats.max = values.back();
  long double sum = 0, sum_abs = 0, sum_squares = 0;
  std::size_t within = 0, gouge = 0, excess = 0;
  std::vector<double> magnitudes(values.size());
  for (std::size_t i = 0; i < values.size(); ++i) {
    const double v = values[i];
    sum += v;
    sum_abs += std::abs(v);
    sum_squares += static_cast<long double>(v) * v;
    if (std::abs(v) <= options.tolerance) ++within;
    const DeviationClass kind = classify(v, stats.band);
    gouge += kind == DeviationClass::Gouge;
    excess += kind == DeviationClass::Excess;
  }
  // |v| in ascending order without a second sort: the negative values reversed, merged with the rest.
  const auto first_non_negative = std::lower_bound(values.begin(), values.end(), 0.0);
  std::vector<double> negatives_reversed;
  negatives_reversed.reserve(static_cast<std::size_t>(first_non_negative - values.begin()));
  for (auto it = first_non_negative; it != values.begin();) negatives_reversed.push_back(-*--it);
  std::merge(negatives_reversed.begin(), negatives_reversed.end(), first_non_negative, values.end(),
             magnitudes.begin());
  for (double& m : magnitudes) m = std::abs(m);  // -0.0 sorts among the non-negative values
  const auto n = static_cast<long double>(values.size());
  stats.mean = static_cast<double>(sum / n);
  stats.mean_abs = static_cast<double>(sum_abs / n);
  stats.rms = static_cast<double>(std::sqrt(sum_squares / n));
  stats.share_within_tolerance = static_cast<double>(within) / static_cast<double>(values.size());
  stats.share_gouge = static_cast<double>(gouge) / static_cast<double>(values.size());
  stats.share_excess = static_cast<double>(excess) / static_cast<double>(values.size());
  stats.share_within_band =
      static_cast<double>(values.size() - gouge - excess) / static_cast<double>(values.size());
  stats.band_histogram = band_histogram(values, stats.band, options.band_bins_per_side);
  stats.max_abs = magnitudes.back();
  stats.p50 = percentile_of_sorted(magnitudes, 50);
  stats.p90 = percentile_of_sorted(magnitudes, 90);
  stats.p99 = percentile_of_sorted(magnitudes, 99);
  stats.p999 = percentile_of_sorted(magnitudes, 99.9);

  const std::size_t bins = std::max<std::size_t>(1, options.histogram_bins);
  Histogram& h = stats.histogram;
  if (stats.max > stats.min) {
    h.edges.resize(bins + 1);
    for (std::size_t i = 0; i <= bins; ++i)
      h.edges[i] = stats.min + (stats.max - stats.min) * static_cast<double>(i) / static_cast<double>(bins);
    h.edges.back() = stats.max;
    h.counts.assign(bins, 0);
    for (double v : values) {
      // Bin by the edges themselves so a value equal to an edge lands in the bin it opens.
      auto bin =
          static_cast<std::size_t>(std::upper_bound(h.edges.begin(), h.edges.end(), v) - h.edges.begin());
      bin = std::min(bin == 0 ? 0 : bin - 1, bins - 1);
      ++h.counts[bin];
    }
  } else {
    h.edges = {stats.min, stats.max};
    h.counts = {values.size()};
  }
  return stats;
}

namespace {

constexpr double kMiss = std::numeric_limits<double>::quiet_NaN();

constexpr std::uint32_t kNoHint = 0xffffffffu;

// Deviation of one point with its normal against `to`; NaN for a miss. `hint` is a triangle
// near p (the answer for the previous, nearby sample) that speeds up the closest-point search
// without changing its result; it is updated to this point's triangle.
double measure_point(const SurfaceQuery& to, DeviationMode mode, const Eigen::Vector3d& p,
                     const Eigen::Vector3d& normal, double max_distance, std::uint32_t* triangle,
                     std::uint32_t* hint) {
  switch (mode) {
    case DeviationMode::Unsigned:
    case DeviationMode::Signed: {
      const ClosestPoint cp = to.closest_point(p, max_distance, *hint);
      if (!cp.found) return kMiss;
      *triangle = *hint = cp.triangle;
      return mode == DeviationMode::Signed ? to.side(p, cp) * cp.distance : cp.distance;
    }
    case DeviationMode::Ray: {
      const RayHit hit = to.nearest_hit_both_ways(p, normal, max_distance);
      if (!hit.hit) return kMiss;
      *triangle = hit.triangle;
      // Signed like the Signed mode: positive when the sample is on the outer side of the hit face.
      const Eigen::Vector3d face = morph::face_normal(to.mesh(), hit.triangle);
      return (p - hit.point).dot(face) < 0 ? -std::abs(hit.t) : std::abs(hit.t);
    }
  }
  return kMiss;
}

// Calls f(begin, end) over consecutive chunks of [0, n): samples in a chunk are neighbours on
// the surface, so each can hint the next. Results do not depend on the chunking.
template <class F>
void for_each_chunk(morph::ExecutionPolicy policy, std::size_t n, F&& f) {
  constexpr std::size_t kChunk = 256;
  const std::size_t chunks = (n + kChunk - 1) / kChunk;
  morph::for_each_index(policy, 0, chunks,
                        [&](std::size_t c) { f(c * kChunk, std::min(n, (c + 1) * kChunk)); });
}

enum class TagSource { Auto, Source, Target };

// Sample normals only where rays are cast along them.
SamplingOptions sampling_for(const DeviationOptions& options) {
  SamplingOptions sampling = options.sampling;
  sampling.vertex_normals = options.mode == DeviationMode::Ray;
  return sampling;
}

std::vector<GroupStats> group_stats(const OneSidedDeviation& result, const morph::TriangleMesh& from,
                                    const morph::TriangleMesh* to, TagSource source,
                                    const DeviationOptions& options) {
  const bool from_tagged = !from.tags.empty();
  const bool to_tagged = to && !to->tags.empty() && !result.target_triangles.empty();
  bool use_source = false;
  switch (source) {
    case TagSource::Source:
      if (!from_tagged) return {};
      use_source = true;
      break;
    case TagSource::Target:
      if (!to_tagged) return {};
      break;
    case TagSource::Auto:
      if (!from_tagged && !to_tagged) return {};
      use_source = from_tagged;
      break;
  }
  using Key = std::tuple<int, std::int32_t, std::int32_t>;
  std::map<Key, std::vector<double>> groups;
  for (std::size_t i = 0; i < result.samples.size(); ++i) {
    const double v = result.values[i];
    morph::FaceTag tag;
    if (use_source) {
      tag = from.tags[result.samples[i].triangle];
    } else {
      if (std::isnan(v)) continue;  // a miss has no target face
      tag = to->tags[result.target_triangles[i]];
    }
    groups[Key{static_cast<int>(tag.kind), tag.source, tag.line}].push_back(v);
  }
  std::vector<GroupStats> out;
  out.reserve(groups.size());
  for (auto& [key, values] : groups) {
    GroupStats g;
    g.tag.kind = static_cast<morph::PatchKind>(std::get<0>(key));
    g.tag.source = std::get<1>(key);
    g.tag.line = std::get<2>(key);
    g.stats = compute_stats(std::move(values), options.stats);
    out.push_back(std::move(g));
  }
  // Worst first; the map order breaks ties, so the selection is deterministic.
  std::stable_sort(out.begin(), out.end(), [](const GroupStats& x, const GroupStats& y) {
    return x.stats.max_abs > y.stats.max_abs;
  });
  if (out.size() > options.worst_groups) out.resize(options.worst_groups);
  return out;
}

OneSidedDeviation measure_samples_tagged(const morph::TriangleMesh& from, std::vector<SurfaceSample> samples,
                                         const SurfaceQuery& to, const DeviationOptions& options,
                                         TagSource source) {
  OneSidedDeviation result;
  result.samples = std::move(samples);
  const std::size_t n = result.samples.size();
  result.values.assign(n, kMiss);
  result.target_triangles.assign(n, 0);
  // Visit the samples by source triangle, so consecutive ones are neighbours and hint each other
  // (face samples are drawn in random order); each value still goes to its own slot.
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  // Vertex samples come in vertex order, already neighbours; only face samples need sorting.
  const bool by_vertex = std::all_of(result.samples.begin(), result.samples.end(),
                                     [](const SurfaceSample& s) { return s.kind == SampleKind::Vertex; });
  if (!by_vertex)
    std::sort(order.begin(), order.end(), [&](std::uint32_t x, std::uint32_t y) {
      const std::uint32_t tx = result.samples[x].triangle, ty = result.samples[y].triangle;
      return tx != ty ? tx < ty : x < y;
    });
  if (options.mode == DeviationMode::Signed) to.prepare_sides();
  morph::Progress& progress = options.progress ? *options.progress : morph::null_progress();
  progress.begin("measuring " + std::to_string(n) + " samples", n);
  for_each_chunk(options.policy, n, [&](std::size_t begin, std::size_t end) {
    std::uint32_t hint = kNoHint;
    for (std::size_t k = begin; k < end; ++k) {
      const std::size_t i = order[k];
      const SurfaceSample& s = result.samples[i];
      result.values[i] = measure_point(to, options.mode, s.position, s.normal, options.max_distance,
                                       &result.target_triangles[i], &hint);
    }
    progress.advance(end - begin);
  });
  progress.end();
  result.stats = compute_stats(result.values, options.stats);
  result.groups = group_stats(result, from, &to.mesh(), source, options);
  return result;
}

}  // namespace

OneSidedDeviation measure_samples(const morph::TriangleMesh& from, std::vector<SurfaceSample> samples,
                                  const SurfaceQuery& to, const DeviationOptions& options) {
  return measure_samples_tagged(from, std::move(samples), to, options, TagSource::Auto);
}

OneSidedDeviation measure_one_sided(const morph::TriangleMesh& from, const SurfaceQuery& to,
                                    const DeviationOptions& options) {
  return measure_samples(from, sample_surface(from, sampling_for(options)), to, options);
}

TwoSidedDeviation measure_two_sided(const SurfaceQuery& query_a, const SurfaceQuery& query_b,
                                    const DeviationOptions& options) {
  const morph::TriangleMesh& a = query_a.mesh();
  const morph::TriangleMesh& b = query_b.mesh();
  TwoSidedDeviation result;
  result.a_to_b = measure_samples_tagged(a, sample_surface(a, sampling_for(options)), query_b, options,
                                         a.tags.empty() ? TagSource::Auto : TagSource::Source);
  result.b_to_a = measure_samples_tagged(b, sample_surface(b, sampling_for(options)), query_a, options,
                                         a.tags.empty() ? TagSource::Auto : TagSource::Target);
  result.hausdorff = std::max(result.a_to_b.stats.max_abs, result.b_to_a.stats.max_abs);
  return result;
}

TwoSidedDeviation measure_two_sided(const morph::TriangleMesh& a, const morph::TriangleMesh& b,
                                    const DeviationOptions& options) {
  return measure_two_sided(SurfaceQuery(a), SurfaceQuery(b), options);
}

OneSidedDeviation measure_against_field(const morph::TriangleMesh& from, const DistanceField& field,
                                        const DeviationOptions& options) {
  if (options.mode == DeviationMode::Ray)
    throw morph::InputError("measure_against_field: ray mode needs a mesh to cast rays at, not a field");
  if (!field) throw morph::InputError("measure_against_field: empty distance field");
  OneSidedDeviation result;
  result.samples = sample_surface(from, options.sampling);
  const std::size_t n = result.samples.size();
  result.values.assign(n, kMiss);
  morph::for_each_index(options.policy, 0, n, [&](std::size_t i) {
    const double v = field(result.samples[i].position);
    const double value = options.mode == DeviationMode::Unsigned ? std::abs(v) : v;
    result.values[i] = std::abs(value) <= options.max_distance ? value : kMiss;
  });
  result.stats = compute_stats(result.values, options.stats);
  result.groups = group_stats(result, from, nullptr, TagSource::Source, options);
  return result;
}

std::vector<double> vertex_deviation(const morph::TriangleMesh& mesh, const SurfaceQuery& target,
                                     DeviationMode mode, double max_distance, morph::ExecutionPolicy policy) {
  std::vector<Eigen::Vector3d> normals;
  if (mode == DeviationMode::Ray) normals = angle_weighted_vertex_normals(mesh);
  std::vector<double> values(mesh.vertices.size(), kMiss);
  if (mode == DeviationMode::Signed) target.prepare_sides();
  for_each_chunk(policy, values.size(), [&](std::size_t begin, std::size_t end) {
    std::uint32_t hint = kNoHint;
    for (std::size_t v = begin; v < end; ++v) {
      std::uint32_t triangle = 0;
      const Eigen::Vector3d normal = normals.empty() ? Eigen::Vector3d::Zero() : normals[v];
      values[v] = measure_point(target, mode, mesh.vertices[v], normal, max_distance, &triangle, &hint);
    }
  });
  return values;
}

}  // namespace raytest
