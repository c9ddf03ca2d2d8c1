// SPDX-License-Identifier: Apache-2.0
#pragma once
// `morphmill study`: one-at-a-time parameter sweeps over jobs (generator tolerance, reference
// voxel size, tool radius, step-over of generated zigzag jobs), with a convergence table (CSV,
// JSON), plots (PLplot), heatmaps of every setting and a self-contained HTML report.
// The study file format is in docs/study.md.
#include <morph/job.h>
#include <morph/progress.h>

#include <atomic>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace morphmill::study {

/// A zigzag pocketing job made from a few numbers, for the step-over sweep.
struct ZigzagSpec {
  std::string name;
  Eigen::Vector3d stock_min = Eigen::Vector3d::Zero(),
                  stock_max = Eigen::Vector3d::Zero();  ///< box, job units
  std::string tool_type = "ballend";                    ///< "ballend" or "sphere"
  double tool_radius = 0, tool_length = 0;
  /// Area covered by the passes (x0, y0, x1, y1) on the top face; passes run along x.
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  double depth = 0;      ///< below the top face, job units
  double step_over = 0;  ///< distance between passes, job units
  double tolerance = 0.01;
};

/// Builds the zigzag job (tool 1, one path). Throws morph::InputError for non-positive sizes.
morph::Job make_zigzag_job(const ZigzagSpec& spec);

/// The parameters a study sweeps.
enum class Parameter { VoxelSize, Tolerance, ToolRadiusScale, StepOver };
const char* to_string(Parameter parameter);

struct StudySpec {
  std::string name;
  std::string description;
  std::string file;  ///< the study file (jobs are relative to it)
  std::vector<std::string> job_paths;
  std::vector<ZigzagSpec> zigzags;
  /// Sweep values; empty: not swept. Voxel sizes are in tool radii (voxel = value x smallest
  /// radius) when voxel_relative_to_tool_radius, else in job units.
  std::vector<double> voxel_sizes, tolerances, tool_radius_scales, step_overs;
  bool voxel_relative_to_tool_radius = true;
  /// Baseline of every parameter not being swept: voxel (same units as voxel_sizes; 0 = verify's
  /// auto_voxel_size), tolerance (0 = the job's).
  double baseline_voxel = 0, baseline_tolerance = 0;
  std::size_t face_samples = 20000;
  std::uint64_t seed = 1;
  bool heatmaps = true;
  int image_width = 480, image_height = 360;
};

/// Reads and checks a study file; throws morph::InputError naming the file and JSON path.
StudySpec load_study(const std::string& path);
StudySpec parse_study(const nlohmann::json& json, const std::string& file);

/// One evaluated setting.
struct StudyRow {
  std::string job;
  Parameter parameter = Parameter::VoxelSize;
  double value = 0;  ///< the swept parameter's value as given in the study
  double tolerance = 0, voxel_size = 0, tool_radius = 0;  ///< job units (smallest tool radius)
  std::optional<double> step_over;
  // Generator (morph).
  double generator_seconds = 0, generator_peak_mib = 0;
  std::size_t generator_triangles = 0, generator_pieces = 0;
  double generator_max_error = 0;  ///< max over both directions generator <-> exact surface
  double generator_mean_error = 0, generator_rms_error = 0;  ///< of generator -> exact
  // Reference (OpenVDB).
  double reference_seconds = 0, reference_peak_mib = 0, reference_grid_mib = 0;
  std::size_t reference_active_voxels = 0, reference_pieces = 0;
  double reference_max_error = 0, reference_mean_error = 0, reference_rms_error = 0;  ///< reference -> exact
  double agreement = 0;  ///< two-sided generator <-> reference Hausdorff
  bool verdict = false;
  /// The job's tools with their shapes and sizes ("T1 flat diameter 6, length 20; ...").
  std::string tools;
  /// Why the generator was not run ("" when it was). Studies run before generator 1 was removed
  /// checked the reference alone for tools it could not build, and their results read back so:
  /// the generator fields are then not measurements, and `verdict` is the reference's check.
  std::string generator_skipped;
  std::vector<std::string> pictures;  ///< heatmap PNGs written, relative to the output directory
  std::string error;                  ///< why the setting could not be evaluated ("" if it was)
};

/// Least-squares fit of log(y) = order * log(x) + log(constant) over the positive pairs.
struct PowerFit {
  double order = 0, constant = 0;
  double r_squared = 0;
  std::size_t points = 0;  ///< pairs used
};
/// Throws morph::InputError with fewer than two usable pairs or all x equal.
PowerFit fit_power_law(const std::vector<double>& x, const std::vector<double>& y);

struct StudyOptions {
  std::string study_path;
  std::string out_dir;
  /// Keep the settings already evaluated in out_dir/settings/ (by an earlier run of the same
  /// study that was stopped) and evaluate only the others.
  bool resume = false;
  /// Explicit cancellation: once this holds a non-zero signal number, no further setting starts;
  /// the table of the settings evaluated so far is written (study.csv, study.json) and the result
  /// says it is incomplete.
  const std::atomic<int>* stop_signal = nullptr;
  morph::Progress* progress = nullptr;
};

struct StudyResult {
  StudySpec spec;
  std::vector<StudyRow> rows;
  /// Per job and error measure: the fitted order of the reference's error against voxel size.
  struct Convergence {
    std::string job, measure;  ///< measure: "mean", "rms", "max"
    std::string tools;         ///< the job's tools, shapes and sizes (StudyRow::tools)
    PowerFit fit;
  };
  std::vector<Convergence> convergence;
  std::vector<std::string> files;
  std::size_t settings = 0;   ///< distinct settings of the study
  std::size_t evaluated = 0;  ///< of which evaluated (or kept from an earlier run)
  std::string stopped;        ///< "interrupted by SIGTERM" when stopped early, else ""
  bool complete() const { return stopped.empty(); }
};

/// Runs the study and writes study.csv, study.json, the plots, heatmaps/ and report.html; each
/// evaluated setting is kept in settings/ as it finishes. Removes the old study.json first. When
/// stopped, writes study.csv and study.json (complete: false) of the settings evaluated only.
StudyResult run_study(const StudyOptions& options);

/// The table as CSV (header + one line per row) and as JSON.
std::string rows_to_csv(const std::vector<StudyRow>& rows);
nlohmann::json result_to_json(const StudyResult& result);

/// A line/point chart written as PNG through PLplot's cairo driver.
struct PlotSeries {
  std::string label;
  std::vector<double> x, y;
  int color = 1;        ///< palette index 1..8
  bool line = true;     ///< join the points
  bool dashed = false;  ///< dashed line
  bool markers = true;  ///< a symbol on each point
};
struct PlotSpec {
  std::string title, x_label, y_label;
  bool log_x = true, log_y = true;
  std::vector<PlotSeries> series;
  int width = 800, height = 600;
};
/// Draws the chart; points that cannot be drawn (non-positive on a log axis, not finite) are
/// skipped. Throws morph::InputError if nothing can be drawn, morph::IoError if the PNG is not
/// written. Not thread-safe (PLplot keeps global state): callers serialise.
void plot_png(const PlotSpec& spec, const std::string& path);

}  // namespace morphmill::study
