// SPDX-License-Identifier: Apache-2.0
// Orchestration of the level-set reference: validation, the up-front memory estimate, the sparse
// sampling of the stock and sweeps, and the face provenance. The OpenVDB work itself is behind
// LevelSetPipeline (level_set_openvdb.cpp).
#include <morph/exceptions.h>
#include <morph/sweep_distance.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>
#include <vdb_ref/reference.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
#include <sstream>

#include "face_tags.h"
#include "level_set.h"
#include "sparse_sampling.h"
#include "straight_sweep.h"

namespace vdb_ref {

using detail::BlockLists;
using detail::DistanceFunction;
using detail::SparseLevelSet;
using detail::VoxelCoord;

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

std::string number(double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.12g", value);
  return buffer;
}

// Arcs and helices are sampled as chords within this fraction of a voxel of the curve: far below
// the level set's own resolution, and each chord's sweep distance is cheap and exact.
constexpr double kChordToleranceVoxels = 0.01;

// Bytes per narrow-band voxel per grid: a 4-byte float in leaf nodes about half filled by a band
// (a band of 2*half_width+1 voxels crosses one or two 8-voxel leaves), plus masks and tree nodes.
constexpr double kBytesPerBandVoxel = 10.0;
// Grids and sample buffers alive at once at the peak (stock, sweep, their samples, the rebuild).
constexpr double kGridsAtPeak = 3.0;
// Output mesh per (surface area / voxel^2): ~2 triangles (indices and tags) and ~1 vertex.
constexpr double kMeshBytesPerSurfaceVoxel = 2.0 * (12 + 12) + 24;
// Fixed cost per grid: each has at least one 32^3-entry internal node (~264 KiB), and small jobs
// were measured at ~6 MiB for their grids, rebuild and meshing buffers whatever their size.
constexpr double kGridFixedBytes = 2.0 * 1024 * 1024;
// One 16^3-entry internal node (~33 KiB) per 128^3 voxels the band crosses (~2 per 128^2 surface
// voxels).
constexpr double kInternalBytesPerSurfaceVoxel = 2.0 * 33.0 * 1024 / (128.0 * 128.0);

void check_interrupted(morph::Progress& progress, const char* stage) {
  if (progress.interrupted()) throw morph::Interrupted(std::string("reference: interrupted during ") + stage);
}

void validate_options(const ReferenceOptions& options) {
  if (!std::isfinite(options.voxel_size) || options.voxel_size <= 0.0)
    throw morph::InputError("reference: the voxel size must be a finite number > 0, got " +
                            number(options.voxel_size));
  if (!std::isfinite(options.half_width_voxels) || options.half_width_voxels < 1.0)
    throw morph::InputError("reference: the narrow-band half width must be >= 1 voxel, got " +
                            number(options.half_width_voxels));
}

std::string stock_name(const morph::Stock& stock) {
  return stock.mesh_path.empty() ? std::string("the stock mesh") : "stock mesh " + stock.mesh_path;
}

// Every directed edge must appear exactly once with its reverse exactly once: closed, manifold
// and consistently wound (OpenVDB's mesh-to-volume needs a watertight mesh for its sign).
void check_closed_mesh(const morph::Stock& stock) {
  const morph::TriangleMesh& mesh = stock.mesh;
  if (mesh.triangles.empty())
    throw morph::InputError("reference: " + stock_name(stock) + " has no triangles");
  mesh.validate(stock_name(stock));
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
  edges.reserve(3 * mesh.triangles.size());
  for (const morph::Triangle& t : mesh.triangles)
    for (int i = 0; i < 3; ++i) edges.emplace_back(t[i], t[(i + 1) % 3]);
  std::sort(edges.begin(), edges.end());
  for (std::size_t i = 0; i < edges.size(); ++i) {
    const auto [a, b] = edges[i];
    if (i + 1 < edges.size() && edges[i + 1] == edges[i])
      throw morph::InputError("reference: " + stock_name(stock) +
                              " is not a closed consistently wound mesh: edge " + std::to_string(a) + "-" +
                              std::to_string(b) + " is used twice in the same direction");
    if (!std::binary_search(edges.begin(), edges.end(), std::make_pair(b, a)))
      throw morph::InputError("reference: " + stock_name(stock) + " is not closed: edge " +
                              std::to_string(a) + "-" + std::to_string(b) +
                              " has no opposite edge (a hole or a flipped face)");
  }
  if (morph::enclosed_volume(mesh) <= 0.0)
    throw morph::InputError("reference: " + stock_name(stock) + " encloses no volume or is wound inward");
}

void validate_job(const morph::Job& job) {
  const morph::Stock& stock = job.stock;
  switch (stock.type) {
    case morph::StockType::Box:
      if (stock.box.isEmpty() || !(stock.box.volume() > 0.0) || !std::isfinite(stock.box.volume()))
        throw morph::InputError("reference: the stock box is empty or not finite");
      break;
    case morph::StockType::Cylinder:
      if (!(stock.radius > 0.0) || !(stock.height > 0.0) || !std::isfinite(stock.radius * stock.height))
        throw morph::InputError("reference: the stock cylinder needs a finite radius and height > 0");
      break;
    case morph::StockType::Mesh:
      check_closed_mesh(stock);
      break;
  }
  for (const morph::Move* move : job.moves()) {
    const morph::Tool& tool = job.tool_of(*move);
    if (!tool.sphere_or_ball_end() && tool.profile.empty())
      throw morph::InputError("reference: tool " + std::to_string(move->tool) + " ('" +
                              morph::to_string(tool.type) +
                              "') has no profile; build it with the constructors of morph/tool.h");
    if (!(tool.radius > 0.0) || !std::isfinite(tool.radius) || !(tool.length >= 0.0) ||
        !std::isfinite(tool.length))
      throw morph::InputError("reference: tool " + std::to_string(tool.number) +
                              " needs a finite radius > 0 and length >= 0");
    if (!move->start.allFinite() || !move->end.allFinite())
      throw morph::InputError("reference: the move at line " + std::to_string(move->line) + " is not finite");
  }
}

double stock_area(const morph::Stock& stock) {
  return morph::surface_area(stock);
}

// Region of the sweep level set that can matter: outside the stock grown by the band the erosion
// is outside whatever the sweeps are.
Eigen::AlignedBox3d sweep_clip_box(const morph::Stock& stock, double band, double voxel_size) {
  const Eigen::AlignedBox3d box = morph::bounds(stock);
  const Eigen::Vector3d grow = Eigen::Vector3d::Constant(band + 2.0 * detail::kLeafDim * voxel_size);
  return Eigen::AlignedBox3d(box.min() - grow, box.max() + grow);
}

// Length of segment a-b inside `box` (Liang-Barsky clipping).
double clipped_length(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::AlignedBox3d& box) {
  double t0 = 0.0, t1 = 1.0;
  const Eigen::Vector3d d = b - a;
  for (int i = 0; i < 3; ++i) {
    if (d[i] == 0.0) {
      if (a[i] < box.min()[i] || a[i] > box.max()[i]) return 0.0;
      continue;
    }
    double u = (box.min()[i] - a[i]) / d[i], v = (box.max()[i] - a[i]) / d[i];
    if (u > v) std::swap(u, v);
    t0 = std::max(t0, u);
    t1 = std::min(t1, v);
    if (t0 > t1) return 0.0;
  }
  return (t1 - t0) * d.norm();
}

// Straight pieces of a move: the move itself, or the chords of an arc or helix. A chord within
// `chord_tolerance` of the curve moves the tool by at most that much, so the union of the chords'
// sweeps is within chord_tolerance of the arc's sweep (the sweep distance is 1-Lipschitz in the
// tool position), and each chord's sweep has a closed form (sphere) or a 1-D convex search.
std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> straight_pieces(const morph::Move& move,
                                                                         double chord_tolerance) {
  if (!move.is_arc()) return {{move.start, move.end}};
  const std::vector<double> ts = morph::chord_parameters(move, chord_tolerance);
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> pieces;
  for (std::size_t i = 1; i < ts.size(); ++i)
    pieces.emplace_back(morph::point_at(move, ts[i - 1]), morph::point_at(move, ts[i]));
  return pieces;
}

struct SweepPiece {
  const morph::Tool* tool = nullptr;
  detail::StraightSweep sweep;
};

std::vector<SweepPiece> sweep_pieces(const morph::Job& job, double chord_tolerance) {
  std::vector<SweepPiece> out;
  // Runs, not moves: a fine raster's steps along one line sweep what the line sweeps.
  for (const morph::SweptRun& run : morph::swept_runs(job))
    for (const auto& [a, b] : straight_pieces(run.move, chord_tolerance))
      out.push_back({run.tool, detail::StraightSweep(*run.tool, a, b)});
  return out;
}

// Surface area the sweep of `move` adds inside `clip`: lateral area along the clipped length plus
// the tool's own surface (an upper bound for the caps).
double swept_area_estimate(const morph::Tool& tool, const morph::Move& move,
                           const Eigen::AlignedBox3d& clip) {
  if (!morph::swept_bounds(tool, move).intersects(clip)) return 0.0;
  const morph::ToolExtent extent = morph::tool_extent(tool);
  const double reach =
      tool.sphere_or_ball_end() ? tool.radius + tool.length : extent.radius + extent.below + extent.above;
  const Eigen::AlignedBox3d grown(clip.min() - Eigen::Vector3d::Constant(reach),
                                  clip.max() + Eigen::Vector3d::Constant(reach));
  double length = 0.0;
  if (move.is_arc()) {
    const std::vector<double> ts = morph::chord_parameters(move, 0.01 * tool.radius);
    for (std::size_t i = 1; i < ts.size(); ++i)
      length += clipped_length(morph::point_at(move, ts[i - 1]), morph::point_at(move, ts[i]), grown);
  } else {
    length = clipped_length(move.start, move.end, grown);
  }
  const double r = tool.radius;
  if (tool.type == morph::ToolType::Sphere) return 2.0 * M_PI * r * length + 4.0 * M_PI * r * r;
  if (tool.type == morph::ToolType::BallEnd) {
    // Half circle, the two walls and the top across the path, plus the whole tool; only the part
    // of the body below the top of the clip box counts.
    const double lowest_centre = std::min(move.start.z(), move.end.z()) + r;
    const double body = std::clamp(clip.max().z() - lowest_centre, 0.0, tool.length);
    const double top = body < tool.length ? 0.0 : 2.0 * r;
    return (M_PI * r + 2.0 * body + top) * length + 4.0 * M_PI * r * r + 2.0 * M_PI * r * body;
  }
  // Across the path: the tool's outline (at most the half circle or flat bottom, the two walls
  // and the top), plus the whole tool; only the part of the tool below the top of the clip box
  // counts. The ball end's half circle bounds any bottom's outline: pi r >= 2 r.
  const double lowest = std::min(move.start.z(), move.end.z()) - extent.below;
  const double wall = std::clamp(clip.max().z() - lowest, 0.0, extent.below + extent.above);
  const double top = lowest + extent.below + extent.above > clip.max().z() ? 0.0 : 2.0 * r;
  return (M_PI * r + 2.0 * wall + top) * length + 4.0 * M_PI * r * r + 2.0 * M_PI * r * wall;
}

// Voxels of the leaf nodes that cover `box` grown by `margin` (0 for an empty box).
double box_voxels(const Eigen::AlignedBox3d& box, double voxel_size, double margin) {
  if (box.isEmpty()) return 0.0;
  double voxels = 1.0;
  for (int a = 0; a < 3; ++a) {
    const double extent = (box.max()[a] - box.min()[a] + 2.0 * margin) / voxel_size + 2.0;
    voxels *= (std::ceil(extent / detail::kLeafDim) + 1.0) * detail::kLeafDim;
  }
  return voxels;
}

// Stage bracket: begin on construction, end on destruction (also when unwinding).
class StageScope {
 public:
  StageScope(morph::Progress& progress, const char* name, std::size_t total) : progress_(progress) {
    progress_.begin(name, total);
  }
  ~StageScope() { progress_.end(); }
  StageScope(const StageScope&) = delete;
  StageScope& operator=(const StageScope&) = delete;

 private:
  morph::Progress& progress_;
};

SparseLevelSet sample_stock(const morph::Stock& stock, double voxel_size, double band, float background,
                            morph::Progress& progress) {
  const DistanceFunction distance = [&stock](const Eigen::Vector3d& p) {
    return morph::analytic_signed_distance(stock, p);
  };
  const auto [lo, hi] = detail::voxel_range(morph::bounds(stock), voxel_size, band);
  BlockLists blocks;
  detail::enumerate_blocks(distance, lo, hi, voxel_size, band, blocks);
  SparseLevelSet out;
  out.leaf_origins = std::move(blocks.leaves);
  out.interior_origins = std::move(blocks.interior_origins);
  out.interior_sizes = std::move(blocks.interior_sizes);
  out.leaf_values.resize(out.leaf_origins.size());
  StageScope stage(progress, "stock", out.leaf_origins.size());
  const std::vector<const DistanceFunction*> functions{&distance};
  std::atomic<bool> stop{false};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, out.leaf_origins.size(), 64),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      if (stop || progress.interrupted()) {
                        stop = true;
                        return;
                      }
                      for (std::size_t i = range.begin(); i < range.end(); ++i)
                        detail::sample_leaf(out.leaf_origins[i], functions, voxel_size, background,
                                            out.leaf_values[i]);
                      progress.advance(range.size());
                    });
  check_interrupted(progress, "stock");
  return out;
}

struct SweepSamples {
  SparseLevelSet field;
  std::size_t leaf_evaluations = 0;
};

SweepSamples sample_sweeps(const std::vector<SweepPiece>& pieces, const Eigen::AlignedBox3d& clip,
                           double voxel_size, double band, float background, morph::Progress& progress) {
  // 1. Per piece, the leaf nodes near its sweep and the blocks deep inside it.
  std::vector<BlockLists> blocks(pieces.size());
  {
    StageScope stage(progress, "sweep culling", pieces.size());
    std::atomic<bool> stop{false};
    tbb::parallel_for(std::size_t(0), pieces.size(), [&](std::size_t i) {
      if (stop || progress.interrupted()) {
        stop = true;
        return;
      }
      const SweepPiece& piece = pieces[i];
      morph::Move segment;
      segment.start = piece.sweep.start();
      segment.end = piece.sweep.end();
      const Eigen::AlignedBox3d region = morph::swept_bounds(*piece.tool, segment).intersection(clip);
      if (!region.isEmpty()) {
        const auto [lo, hi] = detail::voxel_range(region, voxel_size, band);
        const DistanceFunction distance = [&piece](const Eigen::Vector3d& p) {
          return piece.sweep.distance(p);
        };
        detail::enumerate_blocks(distance, lo, hi, voxel_size, band, blocks[i]);
      }
      progress.advance(1);
    });
    check_interrupted(progress, "sweep culling");
  }
  // 2. Group by leaf node: each leaf's values are the minimum over the pieces that reach it,
  // computed independently of every other leaf (deterministic for any thread count).
  std::vector<std::pair<VoxelCoord, std::uint32_t>> pairs;
  SweepSamples out;
  for (std::size_t i = 0; i < blocks.size(); ++i) {
    for (const VoxelCoord& leaf : blocks[i].leaves) pairs.emplace_back(leaf, static_cast<std::uint32_t>(i));
    out.field.interior_origins.insert(out.field.interior_origins.end(), blocks[i].interior_origins.begin(),
                                      blocks[i].interior_origins.end());
    out.field.interior_sizes.insert(out.field.interior_sizes.end(), blocks[i].interior_sizes.begin(),
                                    blocks[i].interior_sizes.end());
    blocks[i] = BlockLists{};
  }
  tbb::parallel_sort(pairs.begin(), pairs.end());
  out.leaf_evaluations = pairs.size();
  std::vector<std::size_t> group_begin;
  for (std::size_t i = 0; i < pairs.size(); ++i)
    if (i == 0 || pairs[i].first != pairs[i - 1].first) group_begin.push_back(i);
  group_begin.push_back(pairs.size());
  const std::size_t leaves = group_begin.size() - 1;
  out.field.leaf_origins.resize(leaves);
  out.field.leaf_values.resize(leaves);
  StageScope stage(progress, "sweep sampling", leaves);
  std::atomic<bool> stop{false};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves, 16),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      if (stop || progress.interrupted()) {
                        stop = true;
                        return;
                      }
                      std::vector<const detail::StraightSweep*> sweeps;
                      for (std::size_t g = range.begin(); g < range.end(); ++g) {
                        sweeps.clear();
                        for (std::size_t k = group_begin[g]; k < group_begin[g + 1]; ++k)
                          sweeps.push_back(&pieces[pairs[k].second].sweep);
                        out.field.leaf_origins[g] = pairs[group_begin[g]].first;
                        detail::sample_sweep_leaf(out.field.leaf_origins[g], sweeps, voxel_size, background,
                                                  out.field.leaf_values[g]);
                      }
                      progress.advance(range.size());
                    });
  check_interrupted(progress, "sweep sampling");
  return out;
}

std::vector<ReferencePiece> assemble_pieces(const std::vector<detail::Segment>& segments) {
  std::vector<ReferencePiece> pieces;
  std::vector<int> piece_of(segments.size(), -1);
  for (std::size_t i = 0; i < segments.size(); ++i) {
    if (segments[i].volume < 0.0) continue;
    piece_of[i] = static_cast<int>(pieces.size());
    pieces.push_back({segments[i].volume, segments[i].area, segments[i].bounds, 0});
  }
  for (std::size_t i = 0; i < segments.size(); ++i) {
    if (segments[i].volume >= 0.0) continue;
    // A void wall whose solid was not found (it cannot be outside every solid) joins the largest.
    int target = segments[i].enclosing >= 0 ? piece_of[segments[i].enclosing] : -1;
    if (target < 0 && !pieces.empty())
      target = static_cast<int>(
          std::max_element(pieces.begin(), pieces.end(),
                           [](const auto& a, const auto& b) { return a.volume < b.volume; }) -
          pieces.begin());
    if (target < 0) continue;
    pieces[target].volume += segments[i].volume;
    pieces[target].area += segments[i].area;
    ++pieces[target].cavities;
  }
  std::sort(pieces.begin(), pieces.end(), [](const ReferencePiece& a, const ReferencePiece& b) {
    if (a.volume != b.volume) return a.volume > b.volume;
    for (int k = 0; k < 3; ++k)
      if (a.bounds.min()[k] != b.bounds.min()[k]) return a.bounds.min()[k] < b.bounds.min()[k];
    return false;
  });
  return pieces;
}

}  // namespace

double ReferenceResult::volume() const {
  double sum = 0.0;
  for (const ReferencePiece& p : pieces) sum += p.volume;
  return sum;
}

double ReferenceResult::area() const {
  double sum = 0.0;
  for (const ReferencePiece& p : pieces) sum += p.area;
  return sum;
}

std::size_t estimate_reference_memory(const morph::Job& job, const ReferenceOptions& options) {
  validate_options(options);
  validate_job(job);
  const double voxel = options.voxel_size;
  const double band = options.half_width_voxels * voxel;
  const Eigen::AlignedBox3d clip = sweep_clip_box(job.stock, band, voxel);
  const double band_width_voxels = 2.0 * options.half_width_voxels + 1.0;
  const double stock_surface_area = stock_area(job.stock);
  double swept_area = 0.0;
  Eigen::AlignedBox3d swept_region;
  for (const morph::Move* move : job.moves()) {
    swept_area += swept_area_estimate(job.tool_of(*move), *move, clip);
    swept_region.extend(morph::swept_bounds(job.tool_of(*move), *move));
  }
  // The sum of the sweeps' areas counts every overlap (a finishing raster overlaps each pass
  // many times over), but the sweep level set cannot hold more voxels than the box its leaves
  // lie in: the sweeps' bounds within the clip box, grown by the band and rounded out to leaves.
  swept_region = swept_region.intersection(clip);
  const double sweep_region_voxels = box_voxels(swept_region, voxel, band);
  const double sweep_surface_voxels = std::min(swept_area / (voxel * voxel), sweep_region_voxels);
  const double area = stock_surface_area + sweep_surface_voxels * voxel * voxel;
  const double surface_voxels = area / (voxel * voxel);
  const double band_voxels = stock_surface_area / (voxel * voxel) * band_width_voxels +
                             std::min(sweep_surface_voxels * band_width_voxels, sweep_region_voxels);
  const double bytes =
      band_voxels * kBytesPerBandVoxel * kGridsAtPeak +
      surface_voxels * (kMeshBytesPerSurfaceVoxel + kInternalBytesPerSurfaceVoxel * kGridsAtPeak) +
      kGridFixedBytes * (kGridsAtPeak + 1.0);
  if (!std::isfinite(bytes) || bytes > static_cast<double>(options.memory_cap_bytes)) {
    throw morph::LimitError(
        "reference: at voxel size " + number(voxel) + " the level sets would need about " +
        number(std::round(bytes / double(1 << 20))) + " MiB (" + number(std::round(band_voxels)) +
        " narrow-band voxels for " + number(area) + " units^2 of stock and swept surface), over the cap of " +
        number(std::round(options.memory_cap_bytes / double(1 << 20))) +
        " MiB: use a larger voxel size or raise the cap");
  }
  return static_cast<std::size_t>(bytes);
}

ReferenceResult compute_reference(const morph::Job& job, const ReferenceOptions& options) {
  const Clock::time_point start = Clock::now();
  ReferenceResult result;
  ReferenceStats& stats = result.stats;
  stats.estimated_bytes = estimate_reference_memory(job, options);
  stats.voxel_size = options.voxel_size;
  stats.half_width_voxels = options.half_width_voxels;
  morph::Progress& progress = options.progress ? *options.progress : morph::null_progress();
  std::optional<tbb::global_control> single_thread;
  if (!options.threaded) single_thread.emplace(tbb::global_control::max_allowed_parallelism, 1);

  const double voxel = options.voxel_size;
  const double band = options.half_width_voxels * voxel;
  detail::LevelSetPipeline pipeline(voxel, options.half_width_voxels, options.progress);
  const float background = pipeline.background();
  std::size_t peak = 0;
  auto note_memory = [&](std::size_t extra) { peak = std::max(peak, pipeline.memory_bytes() + extra); };

  Clock::time_point stage_start = Clock::now();
  if (job.stock.type == morph::StockType::Mesh) {
    StageScope stage(progress, "stock", 1);
    pipeline.set_stock_mesh(job.stock.mesh);
    progress.advance(1);
    note_memory(0);
  } else {
    SparseLevelSet stock = sample_stock(job.stock, voxel, band, background, progress);
    pipeline.set_stock(stock);
    note_memory(stock.bytes());
  }
  stats.stock_seconds = seconds_since(stage_start);

  stage_start = Clock::now();
  {
    const std::vector<SweepPiece> pieces = sweep_pieces(job, kChordToleranceVoxels * voxel);
    SweepSamples sweep =
        sample_sweeps(pieces, sweep_clip_box(job.stock, band, voxel), voxel, band, background, progress);
    stats.sweep_leaf_evaluations = sweep.leaf_evaluations;
    pipeline.set_sweep(sweep.field);
    note_memory(sweep.field.bytes());
  }
  stats.sweep_seconds = seconds_since(stage_start);

  stage_start = Clock::now();
  {
    StageScope stage(progress, "difference", 1);
    pipeline.difference();
    progress.advance(1);
    note_memory(0);
  }
  stats.difference_seconds = seconds_since(stage_start);
  stats.active_voxels = pipeline.active_voxels();
  if (!options.vdb_output_path.empty()) {
    std::vector<std::pair<std::string, std::string>> metadata = {{"units", morph::to_string(job.units)},
                                                                 {"voxel_size", number(options.voxel_size)},
                                                                 {"job", job.name}};
    metadata.insert(metadata.end(), options.vdb_metadata.begin(), options.vdb_metadata.end());
    pipeline.write(options.vdb_output_path, metadata);
  }

  stage_start = Clock::now();
  {
    result.mesh = pipeline.mesh();
    StageScope stage(progress, "mesh", result.mesh.triangle_count());
    detail::tag_faces(job, voxel, result.mesh, progress);
    note_memory(result.mesh.vertices.capacity() * sizeof(Eigen::Vector3d) +
                result.mesh.triangles.capacity() * sizeof(morph::Triangle) +
                result.mesh.tags.capacity() * sizeof(morph::FaceTag));
  }
  stats.mesh_seconds = seconds_since(stage_start);

  stage_start = Clock::now();
  {
    StageScope stage(progress, "segment", 1);
    result.pieces = assemble_pieces(pipeline.segments());
    progress.advance(1);
  }
  stats.segment_seconds = seconds_since(stage_start);
  stats.memory_bytes = peak;
  stats.total_seconds = seconds_since(start);
  return result;
}

std::string path_with_voxel_suffix(const std::string& path, double voxel_size) {
  const std::size_t slash = path.find_last_of('/');
  const std::size_t dot = path.find_last_of('.');
  const std::string suffix = "_v" + number(voxel_size);
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash) || dot == slash + 1)
    return path + suffix;
  return path.substr(0, dot) + suffix + path.substr(dot);
}

std::vector<double> parse_voxel_sizes(const std::string& text, const std::string& what) {
  std::vector<double> sizes;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) {
    const std::size_t first = item.find_first_not_of(" \t");
    const std::size_t last = item.find_last_not_of(" \t");
    const std::string trimmed = first == std::string::npos ? "" : item.substr(first, last - first + 1);
    double value = 0.0;
    std::size_t used = 0;
    try {
      value = std::stod(trimmed, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (trimmed.empty() || used != trimmed.size())
      throw morph::InputError(what + ": '" + trimmed + "' is not a number (expected sizes like 0.4,0.2,0.1)");
    if (!std::isfinite(value) || value <= 0.0)
      throw morph::InputError(what + ": voxel size " + trimmed + " must be a finite number > 0");
    sizes.push_back(value);
  }
  if (sizes.empty()) throw morph::InputError(what + ": no voxel size given");
  return sizes;
}

}  // namespace vdb_ref
