// SPDX-License-Identifier: Apache-2.0
// morphmill reference: the OpenVDB level-set reference of a job's erosion, at one or more voxel
// sizes (a convergence study), with its mesh, optional VDB grid and stats.
#include <morph/exceptions.h>
#include <morph/file_io.h>
#include <morphmill/job_io.h>
#include <morphmill/mesh_io.h>
#include <vdb_ref/reference.h>

#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "cli/cli_conventions.h"  // write_json
#include "cli/commands.h"
#include "cli/memory_cap.h"
#include "cli/terminal_progress.h"
#include "io/provenance.h"

namespace morphmill {

namespace {

struct ReferenceCommandOptions {
  std::string job_path;
  std::string voxels;
  std::string mesh_path;
  std::string vdb_path;
  std::string json_path;
  CLI::Option* json_option = nullptr;
  double half_width = 3.0;
  double memory_cap_gib = 8.0;
  bool ascii = false;
};

nlohmann::json box_json(const Eigen::AlignedBox3d& box) {
  if (box.isEmpty()) return nullptr;
  return {{"min", {box.min().x(), box.min().y(), box.min().z()}},
          {"max", {box.max().x(), box.max().y(), box.max().z()}}};
}

// The morphmill-reference summary (docs/summary-schema.md): the common keys, then the run's figures.
nlohmann::json stats_json(const morph::Job& job, const vdb_ref::ReferenceResult& result,
                          const std::string& mesh_path, const std::string& vdb_path,
                          const Provenance& provenance) {
  const vdb_ref::ReferenceStats& s = result.stats;
  nlohmann::json pieces = nlohmann::json::array();
  for (const vdb_ref::ReferencePiece& p : result.pieces)
    pieces.push_back(
        {{"volume", p.volume}, {"area", p.area}, {"cavities", p.cavities}, {"bounds", box_json(p.bounds)}});
  return {{"format", "morphmill-reference"},
          {"format_version", 1},
          {"provenance", to_json(provenance)},
          {"units", morph::to_string(job.units)},
          {"job", job.name},
          {"job_file", job.file},
          {"voxel_size", s.voxel_size},
          {"half_width_voxels", s.half_width_voxels},
          {"active_voxels", s.active_voxels},
          {"estimated_bytes", s.estimated_bytes},
          {"memory_bytes", s.memory_bytes},
          {"sweep_leaf_evaluations", s.sweep_leaf_evaluations},
          {"seconds",
           {{"stock", s.stock_seconds},
            {"sweep", s.sweep_seconds},
            {"difference", s.difference_seconds},
            {"mesh", s.mesh_seconds},
            {"segment", s.segment_seconds},
            {"total", s.total_seconds}}},
          {"triangles", result.mesh.triangle_count()},
          {"vertices", result.mesh.vertex_count()},
          {"volume", result.volume()},
          {"area", result.area()},
          {"pieces", pieces},
          {"outputs",
           {{"mesh", mesh_path},
            {"vdb", vdb_path.empty() ? nlohmann::json(nullptr) : nlohmann::json(vdb_path)}}}};
}

void run_reference(const ReferenceCommandOptions& options) {
  const std::vector<double> voxels = vdb_ref::parse_voxel_sizes(options.voxels, "--voxel");
  const std::size_t memory_cap = memory_cap_bytes(options.memory_cap_gib);
  const morph::Job job = load_job(options.job_path);
  report_job_warnings(job);
  const bool several = voxels.size() > 1;
  auto output = [&](const std::string& path, double voxel) {
    return path.empty() || !several ? path : vdb_ref::path_with_voxel_suffix(path, voxel);
  };
  std::vector<vdb_ref::ReferenceOptions> runs;
  for (double voxel : voxels) {
    vdb_ref::ReferenceOptions run;
    run.voxel_size = voxel;
    run.half_width_voxels = options.half_width;
    run.memory_cap_bytes = memory_cap;
    run.vdb_output_path = output(options.vdb_path, voxel);
    // Every voxel size is checked (input, memory cap) before the first long computation.
    vdb_ref::estimate_reference_memory(job, run);
    runs.push_back(run);
  }
  // On standard output the JSON is the whole output: one document, an array when several voxel
  // sizes run, and the human summary is left out so that the output parses.
  const bool json_wanted = options.json_option && options.json_option->count() > 0;
  const bool json_on_stdout = json_wanted && is_standard_output(options.json_path);
  nlohmann::json stdout_documents = nlohmann::json::array();
  TerminalProgress progress;
  for (vdb_ref::ReferenceOptions& run : runs) {
    run.progress = &progress;
    const Provenance provenance = make_provenance(
        job_input_files(job),
        {{"command", "reference"}, {"voxel", run.voxel_size}, {"half_width", run.half_width_voxels}},
        morph::to_string(job.units));
    run.vdb_metadata = {{"morphmill_version", provenance.version},
                        {"morphmill_commit", provenance.commit},
                        {"morphmill_provenance", to_json(provenance).dump()}};
    const vdb_ref::ReferenceResult result = vdb_ref::compute_reference(job, run);
    const std::string mesh_path = output(options.mesh_path, run.voxel_size);
    MeshWriteOptions write_options;
    write_options.binary = !options.ascii;
    write_mesh(result.mesh, mesh_path, write_options, provenance_lines(provenance));
    const vdb_ref::ReferenceStats& s = result.stats;
    if (json_wanted) {
      nlohmann::json document = stats_json(job, result, mesh_path, run.vdb_output_path, provenance);
      if (json_on_stdout)
        stdout_documents.push_back(std::move(document));
      else
        write_json(document, output(options.json_path, run.voxel_size));
    }
    if (json_on_stdout) continue;
    std::cout << "reference " << (job.name.empty() ? options.job_path : job.name) << " at voxel "
              << run.voxel_size << ": " << s.active_voxels << " active voxels, " << std::fixed
              << std::setprecision(1) << s.memory_bytes / double(1 << 20) << " MiB, " << std::setprecision(2)
              << s.total_seconds << " s (stock " << s.stock_seconds << ", sweep " << s.sweep_seconds
              << ", difference " << s.difference_seconds << ", mesh " << s.mesh_seconds << ", segment "
              << s.segment_seconds << ")\n"
              << std::defaultfloat << std::setprecision(8) << "  " << result.pieces.size()
              << " piece(s), volume " << result.volume() << ", area " << result.area() << ", "
              << result.mesh.triangle_count() << " triangles -> " << mesh_path
              << (run.vdb_output_path.empty() ? "" : ", " + run.vdb_output_path) << '\n';
    for (std::size_t i = 0; i < result.pieces.size(); ++i)
      std::cout << "    piece " << i << ": volume " << result.pieces[i].volume << ", area "
                << result.pieces[i].area
                << (result.pieces[i].cavities ? ", " + std::to_string(result.pieces[i].cavities) + " cavities"
                                              : "")
                << '\n';
  }
  if (json_on_stdout) write_json(several ? stdout_documents : stdout_documents.at(0), "-");
}

}  // namespace

void register_reference_command(CLI::App& app) {
  auto options = std::make_shared<ReferenceCommandOptions>();
  CLI::App* command = app.add_subcommand(
      "reference",
      "Compute the OpenVDB level-set reference of the job's erosion (stock minus swept tool) at one or\n"
      "more voxel sizes: narrow-band level sets of the stock and of the exact tool sweeps, their CSG\n"
      "difference, its surface (PLY with per-face provenance: source = nearest move, line = its G-code\n"
      "line, -1 on stock faces) and its pieces with volumes and areas. With several voxel sizes each\n"
      "output gets the voxel size before its extension (ref.ply -> ref_v0.2.ply).\n"
      "Example: morphmill reference data/jobs/slots.json --voxel 0.4,0.2,0.1 -o out/ref.ply --json "
      "out/ref.json");
  command->add_option("job", options->job_path, "Job file (JSON, see docs/job-format.md)")->required();
  command
      ->add_option("--voxel", options->voxels,
                   "Voxel size(s) in job units, comma separated (e.g. 0.2 or 0.4,0.2,0.1)")
      ->required();
  command->add_option("-o,--output", options->mesh_path, "Output mesh (PLY keeps the face provenance)")
      ->required();
  command->add_option("--vdb", options->vdb_path, "Also write the erosion level set as an OpenVDB file");
  options->json_option = add_json_option(
      *command, options->json_path,
      "the stats (voxel count, memory, time per stage, pieces with volumes and areas, provenance; with\n"
      "several voxel sizes one file per size, named like the mesh, or one array on standard output)");
  command->add_option("--half-width", options->half_width, "Narrow-band half width in voxels")
      ->capture_default_str()
      ->check(CLI::Range(1.0, 100.0));
  add_memory_cap_option(command, options->memory_cap_gib);
  command->add_flag("--ascii", options->ascii, "Write ASCII instead of binary PLY/STL");
  command->callback([options] { run_reference(*options); });
}

}  // namespace morphmill
