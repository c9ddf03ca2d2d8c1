// morphmill info JOB: the job as understood; morphmill mesh-info MESH: the topology report.
#include <fmt/format.h>
#include <morph/exceptions.h>
#include <morph/topology.h>
#include <morphmill/job_io.h>
#include <morphmill/mesh_io.h>

#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>

#include "commands.h"

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
    if (!t["generator"].get<bool>()) out << "  (erode cannot build this shape yet; reference and verify can)";
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
  bool json = false;
};

}  // namespace

void register_info_commands(CLI::App& app) {
  auto job_options = std::make_shared<InfoOptions>();
  CLI::App* info = app.add_subcommand("info", "Print a job as MorphMill understands it");
  info->description(
      "Print a job as MorphMill understands it: the stock, the tools, each path with its number of\n"
      "moves by kind (rapid, linear, arc) and length, the bounding box of the tool point and every\n"
      "warning (unknown JSON keys, G-code words that were ignored). Reads the G-code and stock mesh\n"
      "the job names. Exit code 0 if the job is valid, 2 if it is not (the message names the file\n"
      "and the JSON path or G-code line).");
  info->footer("Example: morphmill info data/jobs/slots.json --json\nJob format: docs/job-format.md");
  info->add_option("job", job_options->path, "Job file (JSON, see docs/job-format.md)")->required();
  info->add_flag("--json", job_options->json, "Print the summary as JSON instead of a table");
  info->callback([job_options] {
    const json description = describe_job(load_job(job_options->path));
    if (job_options->json)
      std::cout << description.dump(2) << '\n';
    else
      print_job(description, std::cout);
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
  mesh_info->add_option("mesh", mesh_options->path, "Mesh file (.ply, .stl or .obj)")->required();
  mesh_info->add_flag("--json", mesh_options->json, "Print the report as JSON instead of a table");
  mesh_info->callback([mesh_options] {
    const json report = mesh_report_json(read_mesh(mesh_options->path), mesh_options->path);
    if (mesh_options->json)
      std::cout << report.dump(2) << '\n';
    else
      print_mesh_report(report, std::cout);
  });
}

}  // namespace morphmill
