// SPDX-License-Identifier: Apache-2.0
#include "verify/verify.h"

#include "cli/commands.h"
#include "io/deviation_files.h"
#include "verify/view3d.h"
#include "verify/view3d_surface.h"

#include <fmt/format.h>
#include <morph/aabb_tree.h>
#include <morph/erode.h>
#include <morph/exceptions.h>
#include <morph/file_io.h>
#include <morph/mesh_distance.h>
#include <morph/parallel.h>
#include <morph/sweep_distance.h>
#include <morphmill/job_io.h>
#include <morphmill/mesh_io.h>
#include <raytest/heatmap.h>
#include <raytest/render.h>
#include <raytest/surface_query.h>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <numeric>
#include <optional>

namespace morphmill {

namespace fs = std::filesystem;

namespace {

double peak_rss_mib() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

// Linux keeps a resettable high-water mark of the resident set (VmHWM): writing "5" to
// /proc/self/clear_refs resets it to the current size. Returns false where that is not possible.
bool reset_peak_rss() {
  std::ofstream clear("/proc/self/clear_refs");
  clear << "5";
  clear.flush();
  return static_cast<bool>(clear);
}

// VmHWM of /proc/self/status in MiB (falls back to the process peak of getrusage).
double high_water_rss_mib() {
  std::ifstream status("/proc/self/status");
  std::string key;
  while (status >> key) {
    if (key == "VmHWM:") {
      double kib = 0;
      status >> kib;
      return kib / 1024.0;
    }
    std::getline(status, key);
  }
  return peak_rss_mib();
}

class StageClock {
 public:
  explicit StageClock(std::vector<StageRecord>& stages, bool per_stage_peak = false)
      : stages_(stages), per_stage_peak_(per_stage_peak) {}
  template <class F>
  auto run(const std::string& name, F&& f) {
    const bool stage_peak = per_stage_peak_ && reset_peak_rss();
    const auto start = std::chrono::steady_clock::now();
    auto finish = [&] {
      stages_.push_back({name,
                         std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
                         stage_peak ? high_water_rss_mib() : peak_rss_mib()});
    };
    if constexpr (std::is_void_v<decltype(f())>) {
      f();
      finish();
    } else {
      auto result = f();
      finish();
      return result;
    }
  }

 private:
  std::vector<StageRecord>& stages_;
  bool per_stage_peak_ = false;
};

// Moves points of (or near) the exact surface onto it: Newton steps on the exact field along its
// numerical gradient. Points that do not converge (on creases, where the gradient jumps) are dropped.
std::vector<Eigen::Vector3d> project_onto_exact_surface(const morph::ErosionField& field,
                                                        const std::vector<Eigen::Vector3d>& points,
                                                        double step) {
  std::vector<Eigen::Vector3d> projected(points.size(), Eigen::Vector3d::Constant(std::nan("")));
  morph::for_each_index(morph::ExecutionPolicy::Parallel, 0, points.size(), [&](std::size_t i) {
    Eigen::Vector3d p = points[i];
    for (int iteration = 0; iteration < 12; ++iteration) {
      const double value = field.value(p);
      if (std::abs(value) < 1e-9) {
        projected[i] = p;
        return;
      }
      Eigen::Vector3d gradient;
      for (int axis = 0; axis < 3; ++axis) {
        Eigen::Vector3d h = Eigen::Vector3d::Zero();
        h[axis] = step;
        gradient[axis] = (field.value(p + h) - field.value(p - h)) / (2 * step);
      }
      const double g2 = gradient.squaredNorm();
      if (!(g2 > 0.25)) return;  // a distance field has |gradient| = 1 away from creases
      p -= value * gradient / g2;
    }
  });
  std::vector<Eigen::Vector3d> kept;
  for (const auto& p : projected)
    if (!p.hasNaN()) kept.push_back(p);
  return kept;
}

// A level set of voxel h rounds convex edges by about a voxel but truncates acute wedges by about
// h / sin(angle / 2), and loses walls and gaps thinner than a couple of voxels altogether. A sample is
// resolvable when no two parts of the surface within `radius` face more than about 96 degrees
// apart (a right-angled edge or corner is resolvable); only resolvable samples enter the agreement bound.
std::vector<bool> resolvable_samples(const std::vector<raytest::SurfaceSample>& samples,
                                     const morph::TriangleMesh& surface, const morph::AabbTree& triangles,
                                     double radius) {
  std::vector<bool> resolvable(samples.size(), true);
  std::vector<Eigen::Vector3d> normals(surface.triangle_count());
  for (std::size_t t = 0; t < normals.size(); ++t) normals[t] = morph::face_normal(surface, t);
  std::vector<char> flags(samples.size(), 1);
  morph::for_each_index(morph::ExecutionPolicy::Parallel, 0, samples.size(), [&](std::size_t i) {
    const Eigen::Vector3d& p = samples[i].position;
    const Eigen::AlignedBox3d query(p - Eigen::Vector3d::Constant(radius),
                                    p + Eigen::Vector3d::Constant(radius));
    // The distinct directions of the faces within `radius`, each the first met of its kind in the
    // walk's order (a handful near an edge or corner); a sliver triangle has no normal to speak of.
    // A face whose direction is already listed adds nothing, wherever it lies; a new one facing
    // more than ~96 degrees from one listed decides the sample, and the walk stops there.
    thread_local std::vector<Eigen::Vector3d> directions;
    directions.clear();
    const bool facing_against = !triangles.for_each_overlapping_while(query, [&](std::uint32_t t) {
      const Eigen::Vector3d& n = normals[t];
      if (!n.allFinite() || n.squaredNorm() < 0.5) return true;
      for (const Eigen::Vector3d& d : directions)
        if (d.dot(n) > 0.995) return true;
      const auto& tri = surface.triangles[t];
      const Eigen::Vector3d q = morph::closest_point_on_triangle(
          p, surface.vertices[tri[0]], surface.vertices[tri[1]], surface.vertices[tri[2]]);
      if (!((q - p).norm() <= radius)) return true;
      for (const Eigen::Vector3d& d : directions)
        if (d.dot(n) < -0.1) return false;
      directions.push_back(n);
      return true;
    });
    flags[i] = facing_against ? 0 : 1;
  });
  for (std::size_t i = 0; i < samples.size(); ++i) resolvable[i] = flags[i] != 0;
  return resolvable;
}

// One picture of a heatmap: a standard view of the whole part, or a close-up of one place.
struct PictureSpec {
  std::string suffix;  ///< added to the PNG's stem ("" for the first)
  raytest::View view = raytest::View::Iso;
  std::optional<Eigen::AlignedBox3d> focus;
  std::string caption;
};

std::vector<PictureSpec> iso_only() {
  return {{"", raytest::View::Iso, std::nullopt, "iso view"}};
}

// Iso, top and front of the whole part, and a close-up when there is a place to look at.
std::vector<PictureSpec> standard_views(const std::optional<PictureSpec>& closeup) {
  std::vector<PictureSpec> views = {{"", raytest::View::Iso, std::nullopt, "iso view"},
                                    {"_top", raytest::View::Top, std::nullopt, "top view"},
                                    {"_front", raytest::View::Front, std::nullopt, "front view"}};
  if (closeup) views.push_back(*closeup);
  return views;
}

// A close-up of a place: its region's bounds grown by a third, at least 20 band widths and 1% of the
// part across (so the place fills the picture and a band-sized feature spans pixels), at most the part.
PictureSpec closeup_of(const Eigen::Vector3d& at, const Eigen::AlignedBox3d& region, double band,
                       const Eigen::AlignedBox3d& part, const std::string& what) {
  const double part_size = part.diagonal().norm();
  double half = region.isEmpty() ? 0.0 : 0.5 * region.sizes().maxCoeff() * 1.33;
  half = std::min(std::max({half, 20.0 * band, 0.01 * part_size}), 0.5 * part_size);
  const Eigen::Vector3d h = Eigen::Vector3d::Constant(half);
  return {"_closeup", raytest::View::Iso, Eigen::AlignedBox3d(at - h, at + h),
          fmt::format("close-up: {} at ({:.3f}, {:.3f}, {:.3f})", what, at.x(), at.y(), at.z())};
}

// Length of one pixel of `render`'s picture of `mesh`, from two projected points.
double pixel_length(const morph::TriangleMesh& mesh, const raytest::RenderOptions& render) {
  const Eigen::Vector3d along =
      render.view == raytest::View::Iso ? Eigen::Vector3d(1, 1, 0).normalized() : Eigen::Vector3d::UnitX();
  const Eigen::Vector3d p = render.focus ? render.focus->center() : morph::bounds(mesh).center();
  const double pixels =
      (raytest::project_to_pixel(mesh, render, p + along) - raytest::project_to_pixel(mesh, render, p))
          .norm();
  return pixels > 0 ? 1.0 / pixels : 0.0;
}

// Colours on a fixed diverging map centred on zero, its ends at twice the band (the tolerance), so
// the same colour means the same deviation in every picture; the value is interpolated at each
// pixel, then mapped. The PLY and a VTK PolyData beside it (same name, .vtp) carry the values for
// other tools. Returns the PNG names written (png's stem + each view's suffix).
std::vector<std::string> write_heatmap(morph::TriangleMesh mesh, const std::string& scalar,
                                       const std::vector<double>& values, const fs::path& ply,
                                       const fs::path& png, const std::string& unit, int width, int height,
                                       double band, const Provenance& provenance,
                                       const std::vector<PictureSpec>& views = iso_only()) {
  const raytest::ScalarRange range{-2.0 * band, 2.0 * band};
  raytest::apply_heatmap(mesh, scalar, values, raytest::ColorMap::CoolWarm, range);
  write_deviation_ply(mesh, scalar, ply.string(), provenance);
  write_deviation_vtp(mesh, scalar, fs::path(ply).replace_extension(".vtp").string(), provenance);
  std::vector<std::string> written;
  for (const PictureSpec& spec : views) {
    raytest::RenderOptions render;
    render.width = width;
    render.height = height;
    render.view = spec.view;
    render.focus = spec.focus;
    render.scalar = scalar;
    render.color_map = raytest::ColorMap::CoolWarm;
    render.range = range;
    render.unit = unit;
    render.low_caption = "- gouge";
    render.high_caption = "+ excess";
    render.caption = fmt::format("{}; 1 px = {:.3g} {}; band +/-{:.3g} {}", spec.caption,
                                 pixel_length(mesh, render), unit, band, unit);
    const fs::path file = png.parent_path() / (png.stem().string() + spec.suffix + ".png");
    raytest::write_png(raytest::render_mesh(mesh, render), file.string());
    written.push_back(file.filename().string());
  }
  return written;
}

// `value` at every vertex of `mesh`.
std::vector<double> measured_at(const morph::TriangleMesh& mesh,
                                const std::function<double(const Eigen::Vector3d&)>& value) {
  std::vector<double> values(mesh.vertex_count());
  morph::for_each_index(morph::ExecutionPolicy::Parallel, 0, values.size(),
                        [&](std::size_t i) { values[i] = value(mesh.vertices[i]); });
  return values;
}

// The report's 3D view of `surface` with `values` (signed, `unit`, one per vertex it shows); colours
// over +/-2 band as in the pictures, gouge below -band and excess above +band.
View3d view3d_of(ViewSurface surface, std::vector<double> values, double band, const std::string& unit,
                 const std::string& title) {
  View3d view;
  view.mesh = std::move(surface.mesh);
  view.source_triangles = surface.source_triangles;
  view.decimated = surface.decimated;
  view.values = std::move(values);
  view.range = {-2.0 * band, 2.0 * band};
  view.band_low = -band;
  view.band_high = band;
  view.unit = unit;
  view.title = title;
  return view;
}

}  // namespace

double auto_voxel_size(const morph::Job& job) {
  double smallest_radius = std::numeric_limits<double>::infinity();
  for (const morph::Move* move : job.moves())
    smallest_radius = std::min(smallest_radius, job.tool_of(*move).radius);
  if (!std::isfinite(smallest_radius)) smallest_radius = 1.0;
  // Keep the narrow band of the stock's surface below about 2e7 voxels.
  const double area = morph::surface_area(job.stock);
  const double floor_for_memory = std::sqrt(area * 6.0 / 2e7);
  return std::max(smallest_radius / 6.0, floor_for_memory);
}

namespace {

// The reference alone, against the exact surface: what verify can still check when the generator
// is not run. Judged where the surface is resolvable at the voxel size, as the agreement is.
Evaluation evaluate_reference_only(const morph::Job& job, const vdb_ref::ReferenceOptions& reference_options,
                                   const EvaluateOptions& options, StageClock& clock,
                                   Evaluation& evaluation) {
  VerifyOutcome& out = evaluation.outcome;
  vdb_ref::ReferenceResult reference =
      clock.run("reference (OpenVDB)", [&] { return vdb_ref::compute_reference(job, reference_options); });
  out.reference_triangles = reference.mesh.triangle_count();
  out.reference_active_voxels = reference.stats.active_voxels;
  out.reference_topology = morph::topology_report(reference.mesh);
  for (const auto& piece : reference.pieces)
    out.reference_pieces.push_back({piece.volume, piece.area, piece.bounds});
  const morph::ErosionField field(job);
  clock.run("deviation (Embree)", [&] {
    raytest::DeviationOptions deviation;
    deviation.sampling.face_samples = options.face_samples;
    deviation.sampling.seed = options.seed;
    deviation.stats.tolerance = out.tolerance;
    const raytest::DistanceField exact = [&](const Eigen::Vector3d& p) { return field.value(p); };
    out.reference_to_exact = raytest::measure_against_field(reference.mesh, exact, deviation);
  });
  out.reference_bound = std::sqrt(3.0) * out.voxel_size;
  std::vector<Eigen::AlignedBox3d> boxes(reference.mesh.triangle_count());
  for (std::size_t t = 0; t < boxes.size(); ++t)
    for (std::uint32_t v : reference.mesh.triangles[t]) boxes[t].extend(reference.mesh.vertices[v]);
  const morph::AabbTree triangles(std::move(boxes));
  const std::vector<bool> resolvable =
      resolvable_samples(out.reference_to_exact.samples, reference.mesh, triangles, 2.0 * out.voxel_size);
  WorstPlace worst;
  worst.against = "exact surface (largest resolvable, decides the reference's check)";
  for (std::size_t i = 0; i < resolvable.size(); ++i) {
    const double value = out.reference_to_exact.values[i];
    if (std::isnan(value)) continue;
    if (!resolvable[i]) {
      ++out.unresolvable_samples;
      continue;
    }
    ++out.reference_resolvable_samples;
    if (std::abs(value) > out.reference_resolvable_max) {
      out.reference_resolvable_max = std::abs(value);
      worst.position = out.reference_to_exact.samples[i].position;
      worst.deviation = value;
    }
  }
  if (out.reference_resolvable_samples > 0) out.worst.push_back(worst);
  out.reference_converges =
      out.reference_resolvable_samples > 0 && out.reference_resolvable_max <= out.reference_bound;
  evaluation.reference_mesh = std::move(reference.mesh);
  evaluation.reference_stats = reference.stats;
  return std::move(evaluation);
}

}  // namespace

Evaluation evaluate_job(const morph::Job& job, const EvaluateOptions& options) {
  Evaluation evaluation;
  VerifyOutcome& out = evaluation.outcome;
  out.job = job;
  StageClock clock(out.stages, options.per_stage_peak_memory);
  out.tolerance = options.tolerance > 0 ? options.tolerance : job.tolerance;
  if (!(out.tolerance > 0)) throw morph::InputError("--tolerance must be positive");
  out.voxel_size = options.voxel_size > 0 ? options.voxel_size : auto_voxel_size(job);

  vdb_ref::ReferenceOptions reference_options;
  reference_options.voxel_size = out.voxel_size;
  reference_options.progress = options.progress;
  reference_options.vdb_output_path = options.vdb_output_path;
  reference_options.vdb_metadata = options.vdb_metadata;
  reference_options.memory_cap_bytes = options.reference_memory_cap_bytes;
  vdb_ref::estimate_reference_memory(job, reference_options);  // bad input fails before long work

  if (options.reference_only) {
    out.generator_skipped = "--reference-only was given";
    return evaluate_reference_only(job, reference_options, options, clock, evaluation);
  }

  morph::ErodeOptions erode_options;
  erode_options.tolerance = out.tolerance;
  erode_options.progress = options.progress;
  erode_options.memory_cap_bytes = options.generator_memory_cap_bytes;
  morph::ErodeResult eroded =
      clock.run("generator (morph)", [&] { return morph::erode(job, erode_options); });
  vdb_ref::ReferenceResult reference =
      clock.run("reference (OpenVDB)", [&] { return vdb_ref::compute_reference(job, reference_options); });

  out.morph_triangles = eroded.mesh.triangle_count();
  out.generator_steps = eroded.stats.steps;
  out.reference_triangles = reference.mesh.triangle_count();
  out.reference_active_voxels = reference.stats.active_voxels;
  out.morph_topology = morph::topology_report(eroded.mesh);
  out.reference_topology = morph::topology_report(reference.mesh);
  out.morph_pieces = mesh_pieces(eroded.mesh);
  for (const auto& piece : reference.pieces)
    out.reference_pieces.push_back({piece.volume, piece.area, piece.bounds});

  const morph::ErosionField field(job);
  clock.run("deviation (Embree)", [&] {
    if (options.progress) options.progress->begin("verify: deviation", 5);
    raytest::DeviationOptions deviation;
    deviation.mode = raytest::DeviationMode::Signed;
    deviation.sampling.face_samples = options.face_samples;
    deviation.sampling.seed = options.seed;
    deviation.stats.tolerance = out.tolerance;
    const raytest::SurfaceQuery morph_query(eroded.mesh), reference_query(reference.mesh);
    out.morph_to_reference = raytest::measure_one_sided(eroded.mesh, reference_query, deviation);
    if (options.progress) options.progress->advance(1);
    out.reference_to_morph = raytest::measure_one_sided(reference.mesh, morph_query, deviation);
    if (options.progress) options.progress->advance(1);
    const raytest::DistanceField exact = [&](const Eigen::Vector3d& p) { return field.value(p); };
    // The generator's vertices lie on the exact surface; its error is inside its triangles, and
    // a few small bad ones (a fan across a hole) would slip between area-uniform samples.
    raytest::DeviationOptions at_centroids = deviation;
    at_centroids.sampling.centroids = true;
    out.morph_to_exact = raytest::measure_against_field(eroded.mesh, exact, at_centroids);
    if (options.progress) options.progress->advance(1);
    out.reference_to_exact = raytest::measure_against_field(reference.mesh, exact, deviation);
    if (options.progress) options.progress->advance(1);
    // The other direction of the generator's accuracy: points of the exact surface (the reference's
    // samples moved onto it) to the generator's mesh.
    std::vector<Eigen::Vector3d> seeds;
    for (const auto& sample : out.reference_to_exact.samples) seeds.push_back(sample.position);
    const auto on_surface = project_onto_exact_surface(field, seeds, 1e-6 * std::max(1.0, out.voxel_size));
    std::vector<double> distances(on_surface.size());
    morph::for_each_index(morph::ExecutionPolicy::Parallel, 0, on_surface.size(), [&](std::size_t i) {
      const raytest::ClosestPoint closest = morph_query.closest_point(on_surface[i]);
      distances[i] = morph_query.side(on_surface[i], closest) * closest.distance;
    });
    raytest::StatsOptions stats;
    stats.tolerance = out.tolerance;
    out.exact_to_morph = raytest::compute_stats(distances, stats);
    out.exact_to_morph.misses += seeds.size() - on_surface.size();
    if (options.progress) options.progress->end();
  });

  out.generator_within_tolerance =
      out.morph_to_exact.stats.count > 0 && out.morph_to_exact.stats.max_abs <= out.tolerance &&
      out.exact_to_morph.count > 0 && out.exact_to_morph.max_abs <= out.tolerance;
  out.agreement_bound = out.tolerance + std::sqrt(3.0) * out.voxel_size;
  {
    std::vector<Eigen::AlignedBox3d> boxes(eroded.mesh.triangle_count());
    for (std::size_t t = 0; t < boxes.size(); ++t)
      for (std::uint32_t v : eroded.mesh.triangles[t]) boxes[t].extend(eroded.mesh.vertices[v]);
    const morph::AabbTree triangles(std::move(boxes));
    const double radius = 2.0 * out.voxel_size;
    // Judge each comparison where it lands on the generator: for the reference's samples that is
    // their closest point on the generator (a feature the reference lost lies there, not at the sample).
    std::vector<raytest::SurfaceSample> landing = out.reference_to_morph.samples;
    for (std::size_t i = 0; i < landing.size() && i < out.reference_to_morph.target_triangles.size(); ++i) {
      const std::uint32_t t = out.reference_to_morph.target_triangles[i];
      const auto& tri = eroded.mesh.triangles[t];
      landing[i].position =
          morph::closest_point_on_triangle(landing[i].position, eroded.mesh.vertices[tri[0]],
                                           eroded.mesh.vertices[tri[1]], eroded.mesh.vertices[tri[2]]);
      landing[i].normal = morph::face_normal(eroded.mesh, t);
    }
    const std::pair<const raytest::OneSidedDeviation*, const std::vector<raytest::SurfaceSample>*> sides[] = {
        {&out.morph_to_reference, &out.morph_to_reference.samples}, {&out.reference_to_morph, &landing}};
    WorstPlace decisive;
    decisive.against = "reference (largest resolvable, decides the verdict)";
    for (const auto& [side, positions] : sides) {
      const std::vector<bool> resolvable = resolvable_samples(*positions, eroded.mesh, triangles, radius);
      for (std::size_t i = 0; i < resolvable.size(); ++i) {
        if (std::isnan(side->values[i])) continue;
        if (!resolvable[i]) {
          ++out.unresolvable_samples;
          continue;
        }
        ++out.agreement_samples;
        if (std::abs(side->values[i]) > out.resolvable_hausdorff) {
          out.resolvable_hausdorff = std::abs(side->values[i]);
          decisive.position = (*positions)[i].position;
          decisive.deviation = side->values[i];
          const std::uint32_t t =
              side == &out.morph_to_reference ? (*positions)[i].triangle : side->target_triangles[i];
          decisive.tag = t < eroded.mesh.tags.size() ? eroded.mesh.tags[t] : morph::FaceTag{};
        }
      }
    }
    if (out.agreement_samples > 0) out.worst.push_back(decisive);
  }
  out.sides_agree = out.agreement_samples > 0 && out.resolvable_hausdorff <= out.agreement_bound;
  out.pieces_match = match_pieces(out.morph_pieces, out.reference_pieces, out.voxel_size, out.tolerance,
                                  field, &out.pieces_below_resolution);
  evaluation.morph_mesh = std::move(eroded.mesh);
  evaluation.reference_mesh = std::move(reference.mesh);
  evaluation.reference_stats = reference.stats;
  return evaluation;
}

VerifyOutcome run_verify(const VerifyOptions& options) {
  std::vector<StageRecord> load_stage;
  StageClock clock(load_stage);
  const morph::Job job = clock.run("load job", [&] { return load_job(options.job_path); });
  report_job_warnings(job);
  const DesignSpec design_spec = load_design(options.job_path);
  const morph::TriangleMesh design_mesh =
      design_spec.path.empty() ? morph::TriangleMesh{} : read_mesh(design_spec.path);
  // Bad input fails before the output directory is made (evaluate_job checks this again).
  const double tolerance = options.tolerance > 0 ? options.tolerance : job.tolerance;
  if (!(tolerance > 0)) throw morph::InputError("--tolerance must be positive");
  std::error_code error;
  fs::create_directories(options.out_dir, error);
  if (error)
    throw morph::IoError(options.out_dir + ": cannot create the output directory: " + error.message());
  const fs::path dir(options.out_dir);
  const std::string unit = morph::to_string(job.units);
  std::vector<std::string> inputs = job_input_files(job);
  if (!design_spec.path.empty()) inputs.push_back(design_spec.path);
  const Provenance provenance = make_provenance(inputs,
                                                {{"command", "verify"},
                                                 {"voxel", options.voxel_size},
                                                 {"tolerance", options.tolerance},
                                                 {"samples", options.face_samples},
                                                 {"seed", options.seed},
                                                 {"image_size", {options.image_width, options.image_height}},
                                                 {"reference_only", options.reference_only}},
                                                unit);
  const std::vector<std::string> provenance_comments = provenance_lines(provenance);

  EvaluateOptions evaluate;
  evaluate.voxel_size = options.voxel_size;
  evaluate.tolerance = options.tolerance;
  evaluate.face_samples = options.face_samples;
  evaluate.seed = options.seed;
  evaluate.progress = options.progress;
  evaluate.vdb_output_path = (dir / "reference.vdb").string();
  evaluate.reference_only = options.reference_only;
  if (options.memory_cap_bytes > 0) {
    evaluate.generator_memory_cap_bytes = options.memory_cap_bytes;
    evaluate.reference_memory_cap_bytes = options.memory_cap_bytes;
  }
  evaluate.vdb_metadata = {{"morphmill_version", provenance.version},
                           {"morphmill_commit", provenance.commit},
                           {"morphmill_provenance", to_json(provenance).dump()}};
  Evaluation evaluation = evaluate_job(job, evaluate);
  VerifyOutcome out = std::move(evaluation.outcome);
  out.provenance = provenance;
  out.stages.insert(out.stages.begin(), load_stage.begin(), load_stage.end());
  const morph::TriangleMesh& morph_mesh = evaluation.morph_mesh;
  const morph::TriangleMesh& reference_mesh = evaluation.reference_mesh;
  const bool generator_ran = out.generator_skipped.empty();
  if (generator_ran) {
    write_mesh(morph_mesh, (dir / "morph.ply").string(), {}, provenance_comments);
    out.files.push_back("morph.ply");
  }
  write_mesh(reference_mesh, (dir / "reference.ply").string(), {}, provenance_comments);
  out.files.insert(out.files.end(), {"reference.ply", "reference.vdb"});

  const morph::ErosionField field(out.job);
  StageClock picture_clock(out.stages);
  std::string view3d;  // the report's interactive 3D view
  if (!generator_ran) {
    picture_clock.run("pictures", [&] {
      std::vector<double> reference_exact(reference_mesh.vertex_count());
      morph::for_each_index(morph::ExecutionPolicy::Parallel, 0, reference_exact.size(), [&](std::size_t i) {
        reference_exact[i] = field.value(reference_mesh.vertices[i]);
      });
      const double bound = out.reference_bound > 0 ? out.reference_bound : out.tolerance;
      write_heatmap(reference_mesh, "deviation_exact", reference_exact, dir / "reference_vs_exact.ply",
                    dir / "reference_vs_exact.png", unit, options.image_width, options.image_height, bound,
                    provenance);
      ViewSurface shown = view_surface(reference_mesh);
      std::vector<double> values =
          measured_at(shown.mesh, [&](const Eigen::Vector3d& p) { return field.value(p); });
      view3d = view3d_html(
          view3d_of(std::move(shown), std::move(values), bound, unit, "Reference against the exact surface"),
          default_three_dir());
      raytest::RenderOptions plain;
      plain.width = options.image_width;
      plain.height = options.image_height;
      raytest::write_png(raytest::render_mesh(reference_mesh, plain), (dir / "reference.png").string());
      out.files.insert(out.files.end(), {"reference_vs_exact.ply", "reference_vs_exact.vtp", "reference.png",
                                         "reference_vs_exact.png"});
    });
  } else
    picture_clock.run("pictures", [&] {
      const int w = options.image_width, h = options.image_height;
      // The generator's vertices lie on the exact surface; its error is inside its triangles, so they
      // are refined until a feature of a few hundredths of the part shows (capped at 4M triangles).
      Eigen::AlignedBox3d box;
      for (const auto& v : morph_mesh.vertices) box.extend(v);
      const raytest::RefinedMesh refined =
          raytest::refine_long_edges(morph_mesh, std::max(box.diagonal().norm() / 300.0, 1e-9), 4'000'000);
      const morph::TriangleMesh& morph_display = refined.mesh;
      out.region_resolution = refined.max_edge;
      std::vector<double> morph_exact(morph_display.vertex_count()),
          reference_exact(reference_mesh.vertex_count());
      morph::for_each_index(morph::ExecutionPolicy::Parallel, 0, morph_exact.size(),
                            [&](std::size_t i) { morph_exact[i] = field.value(morph_display.vertices[i]); });
      morph::for_each_index(morph::ExecutionPolicy::Parallel, 0, reference_exact.size(), [&](std::size_t i) {
        reference_exact[i] = field.value(reference_mesh.vertices[i]);
      });
      const raytest::SurfaceQuery reference_query(reference_mesh);
      const auto morph_reference =
          raytest::vertex_deviation(morph_display, reference_query, raytest::DeviationMode::Signed);
      const raytest::ToleranceBand exact_band{-out.tolerance, out.tolerance};
      const raytest::ToleranceBand reference_band{-out.agreement_bound, out.agreement_bound};
      auto keep_regions = [&](const std::vector<double>& values, const raytest::ToleranceBand& band,
                              const std::string& against) {
        const auto regions = raytest::find_regions(morph_display, values, band);
        for (std::size_t i = 0; i < regions.size() && i < 10; ++i)
          out.regions.push_back({against, band, regions[i]});
        return regions.size();
      };
      out.exact_regions = keep_regions(morph_exact, exact_band, "exact surface");
      out.reference_regions = keep_regions(morph_reference, reference_band, "reference");
      // The close-up shows the deepest out-of-band region, else the largest deviation.
      std::optional<PictureSpec> closeup;
      const Eigen::AlignedBox3d part = morph::bounds(morph_mesh);
      if (out.exact_regions > 0) {
        const raytest::DeviationRegion& r = out.regions.front().region;
        closeup = closeup_of(r.location, r.bounds, out.tolerance, part,
                             fmt::format("deepest {} {:+.4g} {}", raytest::to_string(r.kind), r.worst, unit));
      } else if (!morph_exact.empty()) {
        std::size_t worst = 0;
        for (std::size_t i = 1; i < morph_exact.size(); ++i)
          if (std::abs(morph_exact[i]) > std::abs(morph_exact[worst])) worst = i;
        closeup = closeup_of(morph_display.vertices[worst], Eigen::AlignedBox3d(), out.tolerance, part,
                             fmt::format("largest deviation {:+.4g} {}", morph_exact[worst], unit));
      }
      const std::vector<std::string> views = write_heatmap(
          morph_display, "deviation_exact", morph_exact, dir / "morph_vs_exact.ply",
          dir / "morph_vs_exact.png", unit, w, h, out.tolerance, provenance, standard_views(closeup));
      out.files.insert(out.files.end(), views.begin() + 1, views.end());
      ViewSurface shown = view_surface(morph_mesh);
      std::vector<double> values =
          measured_at(shown.mesh, [&](const Eigen::Vector3d& p) { return field.value(p); });
      view3d = view3d_html(view3d_of(std::move(shown), std::move(values), out.tolerance, unit,
                                     "Generator against the exact surface"),
                           default_three_dir());
      write_heatmap(morph_display, "deviation_reference", morph_reference, dir / "morph_vs_reference.ply",
                    dir / "morph_vs_reference.png", unit, w, h, out.agreement_bound, provenance);
      write_heatmap(reference_mesh, "deviation_exact", reference_exact, dir / "reference_vs_exact.ply",
                    dir / "reference_vs_exact.png", unit, w, h, out.agreement_bound, provenance);
      raytest::RenderOptions plain;
      plain.width = w;
      plain.height = h;
      raytest::write_png(raytest::render_mesh(morph_mesh, plain), (dir / "morph.png").string());
      raytest::write_png(raytest::render_mesh(reference_mesh, plain), (dir / "reference.png").string());
      out.files.insert(
          out.files.end(),
          {"morph_vs_exact.ply", "morph_vs_reference.ply", "reference_vs_exact.ply", "morph_vs_exact.vtp",
           "morph_vs_reference.vtp", "reference_vs_exact.vtp", "morph.png", "reference.png",
           "morph_vs_exact.png", "morph_vs_reference.png", "reference_vs_exact.png"});
    });

  if (generator_ran && !design_spec.path.empty()) {
    picture_clock.run("design comparison", [&] {
      CompareOptions compare;
      compare.band = default_band(out.job, design_spec.low, design_spec.high);
      compare.face_samples = options.face_samples;
      compare.seed = options.seed;
      out.design = compare_with_design(out.job, morph_mesh, design_mesh, compare);
      out.design_path = design_spec.path;
      const double reach = 2.0 * std::max(-compare.band.low, compare.band.high);
      std::vector<PictureSpec> design_views = iso_only();
      if (!out.design.regions.empty()) {
        const raytest::DeviationRegion& r = out.design.regions.front().region;
        design_views.push_back(
            closeup_of(r.location, r.bounds, reach / 2.0, morph::bounds(morph_mesh),
                       fmt::format("deepest {} {:+.4g} {}", raytest::to_string(r.kind), r.worst, unit)));
      }
      const std::vector<std::string> views =
          write_heatmap(out.design.refined.mesh, "deviation_design", out.design.point_values,
                        dir / "machined_vs_design.ply", dir / "machined_vs_design.png", unit,
                        options.image_width, options.image_height, reach / 2.0, provenance, design_views);
      out.files.insert(out.files.end(), views.begin() + 1, views.end());
      // What a machinist acts on: the 3D view shows the machined part against the design, measured
      // at the vertices it shows (the comparison's own refined surface can have millions).
      ViewSurface shown = view_surface(morph_mesh);
      std::vector<double> shown_values = raytest::vertex_deviation(
          shown.mesh, raytest::SurfaceQuery(design_mesh), raytest::DeviationMode::Signed);
      View3d design_view = view3d_of(std::move(shown), std::move(shown_values), reach / 2.0, unit,
                                     "Machined result against the design");
      design_view.band_low = compare.band.low;
      design_view.band_high = compare.band.high;
      view3d = view3d_html(design_view, default_three_dir());
      out.design.refined = {};
      out.design.point_values.clear();
      out.files.insert(out.files.end(),
                       {"machined_vs_design.ply", "machined_vs_design.vtp", "machined_vs_design.png"});
    });
  }
  { morph::write_file_atomically((dir / "deviation.json").string(), outcome_to_json(out).dump(2) + "\n"); }
  out.files.push_back("deviation.json");
  std::vector<std::pair<std::string, std::string>> pictures;
  if (generator_ran)
    pictures = {{"Generator (morph)", "morph.png"},
                {"Reference (OpenVDB)", "reference.png"},
                {"Generator against the exact surface", "morph_vs_exact.png"},
                {"Generator against the exact surface, top", "morph_vs_exact_top.png"},
                {"Generator against the exact surface, front", "morph_vs_exact_front.png"},
                {"Generator against the exact surface, close-up", "morph_vs_exact_closeup.png"},
                {"Generator against the reference", "morph_vs_reference.png"},
                {"Reference against the exact surface", "reference_vs_exact.png"}};
  else
    pictures = {{"Reference (OpenVDB)", "reference.png"},
                {"Reference against the exact surface", "reference_vs_exact.png"}};
  if (!out.design_path.empty()) {
    pictures.push_back({"Machined result against the design", "machined_vs_design.png"});
    if (fs::exists(dir / "machined_vs_design_closeup.png"))
      pictures.push_back({"Machined result against the design, close-up", "machined_vs_design_closeup.png"});
  }
  write_reports(out, options.out_dir, pictures, view3d);
  out.files.insert(out.files.end(), {"report.md", "report.html"});
  return out;
}

}  // namespace morphmill
