#pragma once
/// \file deviation.h
/// Deviation between two surfaces (or a surface and an exact field): one-sided and two-sided
/// (Hausdorff) statistics, signed and ray modes, and a breakdown by provenance tag.
#include <morph/mesh.h>
#include <morph/parallel.h>
#include <morph/progress.h>
#include <raytest/sampling.h>
#include <raytest/surface_query.h>

#include <functional>
#include <limits>
#include <vector>

namespace raytest {

/// The sign convention of every signed deviation MorphMill reports, stated in its outputs.
/// A measured surface (the machined part, the generator's mesh) against a reference (the design,
/// the exact surface): + where the measured surface lies outside the reference solid (excess:
/// material left where the reference wants none), - where it lies inside (gouge: material removed
/// where the reference wants it).
inline constexpr const char* kSignConvention =
    "+ excess: material left where the reference wants none (measured surface outside the reference "
    "solid); - gouge: material removed where the reference wants it (measured surface inside)";

/// Allowed signed deviation: values in [low, high] are within (low <= 0 <= high, data units),
/// e.g. -0.02 / +0.1 mm for a part that may keep a little stock but must not be gouged.
struct ToleranceBand {
  double low = 0.0;
  double high = 0.0;
  bool empty() const { return low == 0.0 && high == 0.0; }
};

/// Where a signed deviation falls relative to a band.
enum class DeviationClass { Gouge, Within, Excess };
DeviationClass classify(double value, const ToleranceBand& band);
const char* to_string(DeviationClass kind);

/// Counts of values per bin; bin i holds values in [edges[i], edges[i+1]) (the last bin is closed).
struct Histogram {
  std::vector<double> edges;  ///< bins + 1 increasing values, same units as the data
  std::vector<std::size_t> counts;
  std::size_t underflow = 0;  ///< values below edges.front()
  std::size_t overflow = 0;   ///< values above edges.back()
};

struct StatsOptions {
  std::size_t histogram_bins = 20;
  double tolerance = 0.0;  ///< share_within_tolerance counts |value| <= tolerance (units of the data)
  /// Signed band for the band shares and the band histogram; empty: [-tolerance, +tolerance].
  ToleranceBand band;
  /// Bins of the band histogram on each side of zero, each as wide as the band limit on its side.
  std::size_t band_bins_per_side = 4;
};

/// Statistics of a set of deviations (all in the units of the meshes).
struct DeviationStats {
  std::size_t count = 0;   ///< values measured
  std::size_t misses = 0;  ///< samples without a value (ray mode: no hit; max distance exceeded)
  double min = 0, max = 0, mean = 0;
  double rms = 0;      ///< sqrt(mean of value^2)
  double max_abs = 0;  ///< max |value|: the one-sided Hausdorff distance for unsigned values
  double mean_abs = 0;
  /// Percentiles of |value| (linear interpolation between order statistics, like numpy's default).
  double p50 = 0, p90 = 0, p99 = 0, p999 = 0;
  Histogram histogram;  ///< of the values as given (signed in signed mode), over [min, max]
  double tolerance = 0;
  double share_within_tolerance = 0;  ///< fraction of values with |value| <= tolerance, in [0, 1]
  ToleranceBand band;                 ///< the band the shares below refer to
  double share_gouge = 0;             ///< fraction of values below band.low
  double share_within_band = 0;       ///< fraction in [band.low, band.high]
  double share_excess = 0;            ///< fraction above band.high
  /// Bins by tolerance: edges at k * band.low (k = per_side..1), 0 and k * band.high (k = 1..per_side);
  /// a side whose limit is 0 has no bins (its values are under- or overflow). Empty without a band.
  Histogram band_histogram;
};

/// Statistics of `values` (NaN entries are counted as misses). Deterministic.
DeviationStats compute_stats(std::vector<double> values, const StatsOptions& options = {});

/// Percentile q in [0, 100] of sorted data by linear interpolation (numpy's default); 0 if empty.
double percentile_of_sorted(const std::vector<double>& sorted, double q);

enum class DeviationMode {
  Unsigned,  ///< distance to the nearest point
  Signed,    ///< + outside / - inside the target, from its pseudo-normals
  Ray,  ///< along the sample normal both ways, first hit within max_distance; signed by the target's side
};

struct DeviationOptions {
  SamplingOptions sampling;  ///< how each measured surface is sampled
  DeviationMode mode = DeviationMode::Unsigned;
  double max_distance = std::numeric_limits<double>::infinity();  ///< farther samples count as misses
  StatsOptions stats;
  std::size_t worst_groups = 10;  ///< how many provenance groups to keep (worst max |value| first)
  morph::ExecutionPolicy policy = morph::ExecutionPolicy::Parallel;
  /// Told of each direction's measuring as a stage counted in samples; null: silent.
  morph::Progress* progress = nullptr;
};

/// Deviation statistics of the samples sharing one provenance tag.
struct GroupStats {
  morph::FaceTag tag;
  DeviationStats stats;
};

/// Samples on one surface measured against another surface (or a field).
struct OneSidedDeviation {
  std::vector<SurfaceSample> samples;
  std::vector<double> values;  ///< one per sample; NaN for a miss
  /// For each sample, the triangle of the target it was measured to (closest point or ray hit);
  /// empty when measured against a field.
  std::vector<std::uint32_t> target_triangles;
  DeviationStats stats;
  /// Worst groups by provenance (FaceTag): of the sampled mesh's triangles when it has tags,
  /// else of the target triangles when the target has tags; empty when neither has tags.
  std::vector<GroupStats> groups;
};

/// Samples `from` and measures each sample against `to`.
OneSidedDeviation measure_one_sided(const morph::TriangleMesh& from, const SurfaceQuery& to,
                                    const DeviationOptions& options);

/// Measures already drawn `samples` of `from` against `to` (same rules as measure_one_sided).
OneSidedDeviation measure_samples(const morph::TriangleMesh& from, std::vector<SurfaceSample> samples,
                                  const SurfaceQuery& to, const DeviationOptions& options);

/// Both directions and the two-sided Hausdorff distance max(A->B, B->A) of |value|.
struct TwoSidedDeviation {
  OneSidedDeviation a_to_b;
  OneSidedDeviation b_to_a;
  double hausdorff = 0;  ///< max of the two max_abs (mesh units)
};

/// Measures A against B and B against A. Provenance groups of both directions use A's tags
/// when A has them (B->A via the closest triangle of A).
TwoSidedDeviation measure_two_sided(const morph::TriangleMesh& a, const morph::TriangleMesh& b,
                                    const DeviationOptions& options);

/// The same with prebuilt queries (their meshes are A and B), so callers can reuse them.
TwoSidedDeviation measure_two_sided(const SurfaceQuery& a, const SurfaceQuery& b,
                                    const DeviationOptions& options);

/// Signed distance of a point to an exact surface (negative inside), e.g. morph::ErosionField::value.
using DistanceField = std::function<double(const Eigen::Vector3d&)>;

/// Samples `from` and evaluates the exact field at each sample (must be thread-safe when the
/// policy is Parallel). Values are the field's signed values, or their absolute values in
/// Unsigned mode; Ray mode is not defined for a field (throws morph::InputError).
OneSidedDeviation measure_against_field(const morph::TriangleMesh& from, const DistanceField& field,
                                        const DeviationOptions& options);

/// Per-vertex deviation of `mesh` against `target` in the given mode (Ray mode along the
/// angle-weighted vertex normals); NaN where nothing is found within max_distance.
std::vector<double> vertex_deviation(const morph::TriangleMesh& mesh, const SurfaceQuery& target,
                                     DeviationMode mode,
                                     double max_distance = std::numeric_limits<double>::infinity(),
                                     morph::ExecutionPolicy policy = morph::ExecutionPolicy::Parallel);

}  // namespace raytest
