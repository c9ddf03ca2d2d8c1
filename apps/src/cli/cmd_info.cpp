// SPDX-License-Identifier: Apache-2.0
// morphmill info JOB: the job as understood; morphmill mesh-info MESH: the topology report.
#include <fmt/format.h>
#include <morph/exceptions.h>
#include <morph/gcode.h>
#include <morph/topology.h>
#include <morphmill/job_io.h>
#include <morphmill/mesh_io.h>
#include <morphmill/self_intersections.h>

#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>

#include "cli/cli_conventions.h"

#include "cli/commands.h"

namespace morphmill {

namespace {

using nlohmann::json;

std::string number(double x) {
  return fmt::format("{:.6g}", x);
}

std::string triple(const json& v) {
  return "(" + number(v[0].get<double>()) + ", " + number(v[1].get<double>()) + ", " +
         number(v[2].get<double>()) + ")";
}

std::string box_text(const json& box) {
  if (box.is_null()) return "empty";
  return triple(box["min"]) + " .. " + triple(box["max"]);
}

void print_job(const json& d, std::ostream& out) {
  const std::string units = d["units"].get<std::string>();
  out << "Job " << d["name"].get<std::string>() << "  (" << d["file"].get<std::string>() << ")\n";
  if (d.contains("description")) out << "  " << d["description"].get<std::string>() << "\n";
  out << fmt::format("  units {}, tolerance {} {}\n", units, number(d["tolerance"].get<double>()), units);

  const json& s = d["stock"];
  const std::string type = s["type"].get<std::string>();
  out << "\nStock: " << type;
  if (type == "box") out << "  min " << triple(s["min"]) << "  max " << triple(s["max"]);
  if (type == "cylinder")
    out << "  base " << triple(s["base"]) << "  axis " << triple(s["axis"]) << "  radius "
        << number(s["radius"].get<double>()) << "  height " << number(s["height"].get<double>());
  if (type == "mesh")
    out << "  " << s["path"].get<std::string>() << "  (" << s["triangles"].get<std::size_t>()
        << " triangles)";
  out << "\n  bounds " << box_text(s["bounds"]) << "  volume " << number(s["volume"].get<double>()) << " "
      << units << "^3\n";

  out << "\nTools:\n";
  for (const json& t : d["tools"]) {
    out << fmt::format("  T{:<4} {}", t["number"].get<int>(), t["shape"].get<std::string>());
    if (t.contains("length_offset")) out << "  length offset " << number(t["length_offset"].get<double>());
    out << "\n";
  }

  out << "\nPaths:\n";
  out << fmt::format("  {:>3}  {:<28} {:>5} {:>7} {:>7} {:>7} {:>7} {:>12}\n", "#", "source", "tool", "moves",
                     "rapid", "linear", "arc", "length");
  for (const json& p : d["paths"]) {
    std::string tools;
    for (const json& t : p["tools"]) tools += (tools.empty() ? "" : ",") + std::to_string(t.get<int>());
    std::string source = p["source"].get<std::string>();
    if (p.contains("name")) source = p["name"].get<std::string>() + ": " + source;
    if (source.size() > 28) source = "..." + source.substr(source.size() - 25);
    const json& k = p["moves_by_kind"];
    out << fmt::format("  {:>3}  {:<28} {:>5} {:>7} {:>7} {:>7} {:>7} {:>12}\n",
                       p["index"].get<std::size_t>(), source, tools, p["moves"].get<std::size_t>(),
                       k["rapid"].get<std::size_t>(), k["linear"].get<std::size_t>(),
                       k["arc"].get<std::size_t>(), number(p["length"].get<double>()));
  }
  const json& m = d["moves"];
  const json& l = d["path_length"];
  out << fmt::format("\nMoves: {} (rapid {}, linear {}, arc {})\n", m["total"].get<std::size_t>(),
                     m["by_kind"]["rapid"].get<std::size_t>(), m["by_kind"]["linear"].get<std::size_t>(),
                     m["by_kind"]["arc"].get<std::size_t>());
  out << fmt::format("Path length: {} {} (rapid {}, linear {}, arc {})\n", number(l["total"].get<double>()),
                     units, number(l["by_kind"]["rapid"].get<double>()),
                     number(l["by_kind"]["linear"].get<double>()), number(l["by_kind"]["arc"].get<double>()));
  out << "Bounds of the tool point: " << box_text(d["bounds"]) << "\n";
  const json& warnings = d["warnings"];
  out << "\nWarnings: " << warnings.size() << "\n";
  for (const json& w : warnings) {
    const int line = w["line"].get<int>();
    out << "  " << w["file"].get<std::string>() << (line > 0 ? ":" + std::to_string(line) : std::string())
        << ": " << w["message"].get<std::string>() << "\n";
  }
}

json mesh_report_json(const morph::TriangleMesh& mesh, const std::string& path) {
  const morph::TopologyReport r = morph::topology_report(mesh);
  const Eigen::AlignedBox3d box = morph::bounds(mesh);
  json out{{"file", path},
           {"vertices", r.vertices},
           {"unreferenced_vertices", r.unreferenced_vertices},
           {"triangles", r.triangles},
           {"degenerate_triangles", r.degenerate_triangles},
           {"edges", r.edges},
           {"boundary_edges", r.boundary_edges},
           {"non_manifold_edges", r.non_manifold_edges},
           {"inconsistent_edges", r.inconsistent_edges},
           {"non_manifold_vertices", r.non_manifold_vertices},
           {"components", r.components},
           {"euler_characteristic", r.euler_characteristic},
           {"closed_manifold", r.closed_manifold()},
           {"area", r.area},
           {"volume", r.volume}};
  // For a closed orientable surface chi = 2 (components - genus).
  if (r.closed_manifold()) out["genus"] = long(r.components) - r.euler_characteristic / 2;
  json pieces = json::array();
  for (const morph::PieceTopology& piece : r.pieces)
    pieces.push_back({{"triangles", piece.triangles},
                      {"euler_characteristic", piece.euler_characteristic},
                      {"closed_manifold", piece.closed_manifold},
                      {"genus", piece.closed_manifold ? json(piece.genus) : json(nullptr)}});
  out["pieces"] = pieces;
  const SelfIntersections crossings = find_self_intersections(mesh);
  out["self_intersecting_pairs"] = crossings.pairs;
  out["first_self_intersecting_pairs"] = crossings.first_pairs;
  out["valid_solid"] = r.closed_manifold() && crossings.pairs == 0;
  out["bounds"] = box.isEmpty() ? json(nullptr)
                                : json{{"min", {box.min().x(), box.min().y(), box.min().z()}},
                                       {"max", {box.max().x(), box.max().y(), box.max().z()}}};
  if (!mesh.tags.empty()) {
    std::map<std::string, std::size_t> by_kind;
    for (const morph::FaceTag& t : mesh.tags) ++by_kind[morph::to_string(t.kind)];
    out["face_tags"] = by_kind;
  }
  json scalars = json::array();
  for (const morph::VertexScalar& s : mesh.scalars) {
    double lo = 0, hi = 0;
    if (!s.values.empty()) {
      lo = *std::min_element(s.values.begin(), s.values.end());
      hi = *std::max_element(s.values.begin(), s.values.end());
    }
    scalars.push_back({{"name", s.name}, {"min", lo}, {"max", hi}});
  }
  out["vertex_scalars"] = scalars;
  out["vertex_colors"] = !mesh.colors.empty();
  return out;
}

void print_mesh_report(const json& r, std::ostream& out) {
  out << "Mesh " << r["file"].get<std::string>() << "\n";
  auto row = [&](const char* label, const std::string& value) {
    out << fmt::format("  {:<24}{}\n", label, value);
  };
  auto count = [&](const char* key) { return std::to_string(r[key].get<std::size_t>()); };
  row("vertices", count("vertices") + " (+" + count("unreferenced_vertices") + " unreferenced)");
  row("triangles", count("triangles") + " (" + count("degenerate_triangles") + " degenerate)");
  row("edges", count("edges"));
  row("boundary edges", count("boundary_edges"));
  row("non-manifold edges", count("non_manifold_edges"));
  row("inconsistent edges", count("inconsistent_edges"));
  row("non-manifold vertices", count("non_manifold_vertices"));
  row("components", count("components"));
  row("Euler characteristic", std::to_string(r["euler_characteristic"].get<long>()));
  if (r.contains("genus")) row("genus", std::to_string(r["genus"].get<long>()));
  row("closed manifold", r["closed_manifold"].get<bool>() ? "yes" : "no");
  std::string crossings = count("self_intersecting_pairs") + " pairs of triangles";
  if (!r["first_self_intersecting_pairs"].empty()) {
    crossings += " (first:";
    for (const json& pair : r["first_self_intersecting_pairs"])
      crossings += " " + std::to_string(pair[0].get<std::uint32_t>()) + "&" +
                   std::to_string(pair[1].get<std::uint32_t>());
    crossings += ")";
  }
  row("self-intersections", crossings);
  row("valid solid", r["valid_solid"].get<bool>() ? "yes (closed, oriented, no self-intersections)" : "no");
  constexpr std::size_t kPiecesShown = 20;
  const json& pieces = r["pieces"];
  for (std::size_t i = 0; i < pieces.size() && i < kPiecesShown; ++i) {
    const json& piece = pieces[i];
    row(i == 0 ? "pieces" : "",
        fmt::format("#{}: {} triangles, {}", i + 1, piece["triangles"].get<std::size_t>(),
                    piece["closed_manifold"].get<bool>()
                        ? "closed, genus " + std::to_string(piece["genus"].get<long>())
                        : "not closed (Euler characteristic " +
                              std::to_string(piece["euler_characteristic"].get<long>()) + ")"));
  }
  if (pieces.size() > kPiecesShown) row("", fmt::format("... {} more", pieces.size() - kPiecesShown));
  row("area", number(r["area"].get<double>()));
  row("enclosed volume",
      number(r["volume"].get<double>()) +
          (r["closed_manifold"].get<bool>() ? "" : "  (meaningless: the mesh is not closed)"));
  row("bounds", box_text(r["bounds"]));
  if (r.contains("face_tags")) {
    std::string tags;
    for (auto it = r["face_tags"].begin(); it != r["face_tags"].end(); ++it)
      tags += (tags.empty() ? "" : ", ") + it.key() + " " + std::to_string(it.value().get<std::size_t>());
    row("face tags", tags);
  }
  for (const json& s : r["vertex_scalars"])
    row("vertex scalar", s["name"].get<std::string>() + " in [" + number(s["min"].get<double>()) + ", " +
                             number(s["max"].get<double>()) + "]");
  if (r["vertex_colors"].get<bool>()) row("vertex colours", "yes");
}

struct InfoOptions {
  std::string path;
  std::string json_path;  // --json FILE ('-' or no value: standard output)
  CLI::Option* json_option = nullptr;
  bool moves = false;
  std::string format = "text";
  // G-code read directly (not through a job):
  std::string units = "mm";
  std::string var_file;
  std::vector<double> start;
  bool block_delete = true;
};

bool is_job_file(const std::string& path) {
  return path.size() >= 5 && path.compare(path.size() - 5, 5, ".json") == 0;
}

json vector_json(const Eigen::Vector3d& v) {
  return json::array({v.x(), v.y(), v.z()});
}

/// The moves as understood: tool tip in machine coordinates (job units), kind, arc centre, axis
/// and sweep, tool, source line, feed. Deterministic, for diffing against another interpreter.
json moves_json(const std::vector<morph::Path>& paths, const std::string& file, morph::Units units,
                const std::vector<morph::Warning>& warnings, const std::vector<morph::Warning>& messages) {
  json out;
  out["file"] = file;
  out["units"] = morph::to_string(units);
  json list = json::array();
  for (std::size_t p = 0; p < paths.size(); ++p) {
    for (const morph::Move& m : paths[p].moves) {
      json move;
      move["path"] = p;
      move["line"] = m.line;
      move["kind"] = morph::to_string(m.kind);
      move["tool"] = m.tool;
      move["start"] = vector_json(m.start);
      move["end"] = vector_json(m.end);
      if (m.is_arc()) {
        move["center"] = vector_json(m.center);
        move["axis"] = vector_json(m.axis);
        move["sweep"] = m.sweep;
      }
      move["feed"] = m.feed;
      list.push_back(std::move(move));
    }
  }
  out["moves"] = std::move(list);
  auto notes = [](const std::vector<morph::Warning>& ws) {
    json a = json::array();
    for (const morph::Warning& w : ws)
      a.push_back({{"file", w.file}, {"line", w.line}, {"message", w.message}});
    return a;
  };
  out["warnings"] = notes(warnings);
  out["messages"] = notes(messages);
  return out;
}

void print_moves(const json& d, std::ostream& out) {
  out << "Moves of " << d["file"].get<std::string>() << " (tool tip, machine coordinates, "
      << d["units"].get<std::string>() << ")\n";
  for (const json& m : d["moves"]) {
    out << fmt::format("  line {:>6}  T{:<3} {:<6} {} -> {}", m["line"].get<int>(), m["tool"].get<int>(),
                       m["kind"].get<std::string>(), triple(m["start"]), triple(m["end"]));
    if (m.contains("center"))
      out << fmt::format("  centre {} axis {} sweep {} rad", triple(m["center"]), triple(m["axis"]),
                         number(m["sweep"].get<double>()));
    out << '\n';
  }
  for (const json& w : d["warnings"])
    out << fmt::format("warning: {}:{}: {}\n", w["file"].get<std::string>(), w["line"].get<int>(),
                       w["message"].get<std::string>());
  for (const json& w : d["messages"])
    out << fmt::format("message: {}:{}: {}\n", w["file"].get<std::string>(), w["line"].get<int>(),
                       w["message"].get<std::string>());
}

// `info --json job.json`: --json takes an optional file, so it took the job; without another
// argument that is what the user meant (the summary goes to standard output).
void take_job_from_json_option(InfoOptions& o, const std::string& what = "a job file") {
  if (o.path.empty() && !o.json_path.empty() && o.json_path != "-") std::swap(o.path, o.json_path);
  if (o.path.empty()) throw morph::InputError(what + " is required (see --help)");
}

json read_moves(const InfoOptions& o) {
  if (is_job_file(o.path)) {
    const morph::Job job = load_job(o.path);
    return moves_json(job.paths, o.path, job.units, job.warnings, {});
  }
  morph::GcodeOptions options;
  options.job_units = o.units == "inch" ? morph::Units::Inch : morph::Units::Millimetre;
  options.var_file = o.var_file;
  options.block_delete = o.block_delete;
  if (!o.start.empty()) options.start = Eigen::Vector3d(o.start[0], o.start[1], o.start[2]);
  morph::GcodeResult result = morph::read_gcode(o.path, options);
  std::vector<morph::Path> paths(1);
  paths[0] = std::move(result.path);
  return moves_json(paths, o.path, options.job_units, result.warnings, result.messages);
}

}  // namespace

void register_info_commands(CLI::App& app) {
  auto job_options = std::make_shared<InfoOptions>();
  CLI::App* info = app.add_subcommand("info", "Print a job as MorphMill understands it");
  info->description(
      "Print a job as MorphMill understands it: the stock, the tools, each path with its number of\n"
      "moves by kind (rapid, linear, arc) and length, the bounding box of the tool point and every\n"
      "warning (unknown JSON keys, G-code words that were ignored). Reads the G-code and stock mesh\n"
      "the job names. With --moves, every move as understood instead, of a job or of a G-code file.\n"
      "Exit code 0 if the job is valid, 2 if it is not (the message names the file and the JSON path\n"
      "or G-code line).");
  info->footer(
      "Examples:\n"
      "  morphmill info data/jobs/slots.json --json\n"
      "  morphmill info --moves data/gcode/conformance/cycles.ngc --format json --start 0,0,0\n"
      "Job format: docs/job-format.md; G-code: docs/gcode.md");
  info->add_option("job", job_options->path,
                   "Job file (JSON, see docs/job-format.md), or with --moves a G-code file");
  job_options->json_option = add_json_option(*info, job_options->json_path, "the summary");
  info->add_option("--format", job_options->format, "Output format")->check(CLI::IsMember({"text", "json"}));
  info->add_flag(
      "--moves", job_options->moves,
      "Print every move as understood: tool tip in machine coordinates (job units), kind, arc centre,\n"
      "axis and sweep, tool, source line, feed. Takes a job (.json) or a G-code file (any other\n"
      "extension), so that MorphMill's reading can be diffed against another interpreter's");
  info->add_option("--units", job_options->units, "G-code file only: the units of the moves")
      ->check(CLI::IsMember({"mm", "inch"}));
  info->add_option("--var-file", job_options->var_file,
                   "G-code file only: a LinuxCNC parameter file (work offsets, G28/G30 positions)")
      ->check(CLI::ExistingFile);
  info->add_option(
          "--start", job_options->start,
          "G-code file only: where the tool tip is before the first line, X,Y,Z (else moves start once\n"
          "X, Y and Z are known)")
      ->delimiter(',')
      ->expected(3);
  info->add_flag("!--no-block-delete", job_options->block_delete,
                 "G-code file only: run lines starting with '/' (block delete switch off)");
  info->callback([job_options] {
    take_job_from_json_option(*job_options);
    const bool as_json = job_options->json_option->count() > 0 || job_options->format == "json";
    if (job_options->moves) {
      const json moves = read_moves(*job_options);
      if (as_json)
        write_json(moves, job_options->json_path);
      else
        print_moves(moves, std::cout);
      return;
    }
    const morph::Job job = load_job(job_options->path);
    const json description = describe_job(job);
    if (as_json)
      write_json(description, job_options->json_path);
    else
      print_job(description, std::cout);
    report_job_warnings(job, false);
  });

  auto mesh_options = std::make_shared<InfoOptions>();
  CLI::App* mesh_info = app.add_subcommand("mesh-info", "Print the topology report of a mesh file");
  mesh_info->description(
      "Print the topology report of a triangle mesh (PLY, STL or OBJ): vertices, triangles, edges,\n"
      "boundary edges (one face), non-manifold edges (three or more faces), inconsistently oriented\n"
      "edges, non-manifold vertices (fan not a single disc), edge-connected components, Euler\n"
      "characteristic, area, enclosed volume and bounds; also PLY face tags and vertex scalars.\n"
      "A mesh is a valid stock or result when it is a closed manifold. Exit code 0 when the file was\n"
      "read (whatever the report says), 2 when it cannot be read.");
  mesh_info->footer("Example: morphmill mesh-info data/meshes/cube.stl --json\nFormats: docs/mesh-io.md");
  mesh_info->add_option("mesh", mesh_options->path, "Mesh file (.ply, .stl or .obj)");
  mesh_options->json_option = add_json_option(*mesh_info, mesh_options->json_path, "the report");
  mesh_info->callback([mesh_options] {
    take_job_from_json_option(*mesh_options, "a mesh file");
    const json report = mesh_report_json(read_mesh(mesh_options->path), mesh_options->path);
    if (mesh_options->json_option->count() > 0)
      write_json(report, mesh_options->json_path);
    else
      print_mesh_report(report, std::cout);
  });
}

}  // namespace morphmill
