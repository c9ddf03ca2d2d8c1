// SPDX-License-Identifier: Apache-2.0
// verify's outputs for people: report.md and a self-contained report.html, plus the JSON.
#include <fmt/format.h>
#include <morph/exceptions.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>

#include "io/atomic_output.h"
#include "verify/html.h"
#include "verify/verify.h"

namespace morphmill {

namespace fs = std::filesystem;

namespace {

std::string tag_text(const morph::FaceTag& tag) {
  if (tag.kind == morph::PatchKind::Unknown) return "-";
  if (tag.kind == morph::PatchKind::StockFace || tag.kind == morph::PatchKind::CutSurface)
    return fmt::format("{} {}", morph::to_string(tag.kind), tag.source);
  if (tag.source < 0) return fmt::format("{} (stock)", morph::to_string(tag.kind));
  return fmt::format("{} move {} (line {})", morph::to_string(tag.kind), tag.source, tag.line);
}

// A simple table model rendered both as Markdown and as HTML.
struct Table {
  std::string title;
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
};

std::string markdown(const Table& table) {
  std::ostringstream out;
  out << "### " << table.title << "\n\n|";
  for (const auto& h : table.header) out << ' ' << h << " |";
  out << "\n|";
  for (std::size_t i = 0; i < table.header.size(); ++i) out << "---|";
  out << '\n';
  for (const auto& row : table.rows) {
    out << '|';
    for (const auto& cell : row) out << ' ' << cell << " |";
    out << '\n';
  }
  out << '\n';
  return out.str();
}

std::string html(const Table& table) {
  std::ostringstream out;
  out << "<h3>" << html_escape(table.title) << "</h3>\n<table>\n<tr>";
  for (const auto& h : table.header) out << "<th>" << html_escape(h) << "</th>";
  out << "</tr>\n";
  for (const auto& row : table.rows) {
    out << "<tr>";
    for (const auto& cell : row) out << "<td>" << html_escape(cell) << "</td>";
    out << "</tr>\n";
  }
  out << "</table>\n";
  return out.str();
}

std::string number(double value) {
  return fmt::format("{:.6g}", value);
}
std::string yes_no(bool value) {
  return value ? "yes" : "NO";
}

Table provenance_table(const Provenance& p) {
  Table t{"Provenance", {"item", "value"}, {}};
  t.rows = {{"program", p.program + " " + p.version},
            {"commit", p.commit},
            {"command line", p.command_line},
            {"units", p.units}};
  for (const InputFile& f : p.inputs) t.rows.push_back({"input " + f.path, "SHA-256 " + f.sha256});
  t.rows.push_back({"options", p.options.dump()});
  t.rows.push_back({"machine", fmt::format("{} ({} threads)", p.machine, p.threads)});
  t.rows.push_back({"date (UTC)", p.date_utc});
  return t;
}

std::vector<Table> tables(const VerifyOutcome& o) {
  const std::string u = morph::to_string(o.job.units);
  std::vector<Table> result;
  result.push_back({"Job",
                    {"item", "value"},
                    {{"name", o.job.name},
                     {"file", o.job.file},
                     {"stock", morph::to_string(o.job.stock.type)},
                     {"moves", std::to_string(o.job.move_count())},
                     {"tolerance", number(o.tolerance) + " " + u},
                     {"reference voxel", number(o.voxel_size) + " " + u}}});
  Table tools{"Tools", {"tool", "shape and sizes (" + u + ")", "moves", "length offset"}, {}};
  std::map<int, std::size_t> moves_by_tool;
  for (const morph::Move* m : o.job.moves()) ++moves_by_tool[m->tool];
  for (const auto& [tool_number, tool] : o.job.tools)
    tools.rows.push_back(
        {"T" + std::to_string(tool_number), morph::describe(tool),
         std::to_string(moves_by_tool.count(tool_number) ? moves_by_tool.at(tool_number) : 0),
         number(tool.length_offset)});
  result.push_back(tools);
  Table programs{"Paths (programs in order)", {"#", "path", "moves", "tools used (moves)"}, {}};
  for (std::size_t i = 0; i < o.job.paths.size(); ++i) {
    const morph::Path& path = o.job.paths[i];
    std::map<int, std::size_t> used;
    for (const morph::Move& m : path.moves) ++used[m.tool];
    std::string list;
    for (const auto& [t, n] : used) list += (list.empty() ? "" : ", ") + fmt::format("T{} ({})", t, n);
    programs.rows.push_back({std::to_string(i + 1), path.name.empty() ? path.source : path.name,
                             std::to_string(path.moves.size()), list.empty() ? "-" : list});
  }
  result.push_back(programs);
  if (!o.job.warnings.empty()) {
    Table warnings{"Warnings", {"file", "line", "warning"}, {}};
    for (const morph::Warning& w : o.job.warnings)
      warnings.rows.push_back({w.file, w.line > 0 ? std::to_string(w.line) : "-", w.message});
    result.push_back(warnings);
  }
  Table stages{"Stages", {"stage", "seconds", "peak memory (MiB)"}, {}};
  for (const auto& s : o.stages)
    stages.rows.push_back({s.name, fmt::format("{:.2f}", s.seconds), fmt::format("{:.0f}", s.peak_rss_mib)});
  result.push_back(stages);
  // Without the generator its columns and rows say so: a zero there would read as a measurement.
  const bool generator_ran = o.generator_skipped.empty();
  auto generator_cell = [&](const std::string& text) {
    return generator_ran ? text : std::string("not run");
  };
  std::size_t fallbacks_fired = 0;
  for (const morph::StepCount& step : o.generator_steps)
    if (step.fallback) fallbacks_fired += step.count;
  result.push_back({"Surfaces",
                    {"", "generator (morph)", "reference (OpenVDB)"},
                    {{"triangles", generator_cell(std::to_string(o.morph_triangles)),
                      std::to_string(o.reference_triangles)},
                     {"active voxels", "-", std::to_string(o.reference_active_voxels)},
                     {"closed manifold", generator_cell(yes_no(o.morph_topology.closed_manifold())),
                      yes_no(o.reference_topology.closed_manifold())},
                     {"boundary edges", generator_cell(std::to_string(o.morph_topology.boundary_edges)),
                      std::to_string(o.reference_topology.boundary_edges)},
                     {"fallbacks fired (target 0)", generator_cell(std::to_string(fallbacks_fired)), "-"},
                     {"volume (" + u + "^3)", generator_cell(number(o.morph_topology.volume)),
                      number(o.reference_topology.volume)},
                     {"area (" + u + "^2)", generator_cell(number(o.morph_topology.area)),
                      number(o.reference_topology.area)}}});
  Table pieces{"Pieces (largest first)", {"piece", "generator volume", "reference volume", "difference"}, {}};
  const std::size_t n = std::max(o.morph_pieces.size(), o.reference_pieces.size());
  for (std::size_t i = 0; i < n; ++i) {
    const bool m = i < o.morph_pieces.size(), r = i < o.reference_pieces.size();
    pieces.rows.push_back({std::to_string(i + 1), m ? number(o.morph_pieces[i].volume) : generator_cell("-"),
                           r ? number(o.reference_pieces[i].volume) : "-",
                           m && r ? number(o.morph_pieces[i].volume - o.reference_pieces[i].volume) : "-"});
  }
  result.push_back(pieces);
  Table deviation{"Signed deviation (" + u + "; + excess, - gouge; band -/+ tolerance)",
                  {"from -> to", "samples", "min", "max", "mean", "RMS", "max |d|", "p99 |d|", "gouge",
                   "within", "excess"},
                  {}};
  auto percent = [](double share) { return fmt::format("{:.3f}%", 100.0 * share); };
  auto row = [&](const std::string& name, const raytest::DeviationStats& s) {
    deviation.rows.push_back({name, std::to_string(s.count), number(s.min), number(s.max), number(s.mean),
                              number(s.rms), number(s.max_abs), number(s.p99), percent(s.share_gouge),
                              percent(s.share_within_band), percent(s.share_excess)});
  };
  if (generator_ran) {
    row("generator -> exact", o.morph_to_exact.stats);
    row("exact -> generator", o.exact_to_morph);
  }
  row("reference -> exact", o.reference_to_exact.stats);
  if (generator_ran) {
    row("generator -> reference", o.morph_to_reference.stats);
    row("reference -> generator", o.reference_to_morph.stats);
  }
  result.push_back(deviation);
  const raytest::Histogram& h = o.morph_to_exact.stats.band_histogram;
  if (!h.counts.empty()) {
    const double n = static_cast<double>(std::max<std::size_t>(1, o.morph_to_exact.stats.count));
    Table histogram{"Histogram of generator -> exact (bins of one tolerance, " + u + ")",
                    {"from", "to", "samples", "share"},
                    {}};
    auto bin = [&](const std::string& from, const std::string& to, std::size_t count) {
      histogram.rows.push_back({from, to, std::to_string(count), percent(static_cast<double>(count) / n)});
    };
    bin("-inf", number(h.edges.front()), h.underflow);
    for (std::size_t i = 0; i < h.counts.size(); ++i)
      bin(number(h.edges[i]), number(h.edges[i + 1]), h.counts[i]);
    bin(number(h.edges.back()), "+inf", h.overflow);
    result.push_back(histogram);
  }
  if (generator_ran) {
    Table moves{"Worst moves (generator -> exact, by the face the sample lies on)",
                {"made by", "samples", "min", "max", "max |d|"},
                {}};
    for (const auto& g : o.morph_to_exact.groups)
      moves.rows.push_back({tag_text(g.tag), std::to_string(g.stats.count), number(g.stats.min),
                            number(g.stats.max), number(g.stats.max_abs)});
    result.push_back(moves);
    Table regions{
        fmt::format("Regions out of the band ({} against the exact surface, {} against the reference; "
                    "on the generator's surface refined to {} {})",
                    o.exact_regions, o.reference_regions, number(o.region_resolution), u),
        {"against", "band", "kind", "depth", "area (" + u + "^2)", "x", "y", "z", "made by"},
        {}};
    for (const auto& r : o.regions) {
      std::string made_by;
      for (std::size_t i = 0; i < r.region.sources.size() && i < 3; ++i)
        made_by += (i ? "; " : "") + tag_text(r.region.sources[i].tag);
      regions.rows.push_back({r.against, fmt::format("{} / +{}", number(r.band.low), number(r.band.high)),
                              raytest::to_string(r.region.kind), number(r.region.worst),
                              number(r.region.area), number(r.region.location.x()),
                              number(r.region.location.y()), number(r.region.location.z()),
                              made_by.empty() ? "-" : made_by});
    }
    result.push_back(regions);
  }
  Table worst{"Decisive place", {"against", "deviation", "x", "y", "z", "made by"}, {}};
  for (const auto& w : o.worst)
    worst.rows.push_back({w.against, number(w.deviation), number(w.position.x()), number(w.position.y()),
                          number(w.position.z()), tag_text(w.tag)});
  result.push_back(worst);
  if (!o.design_path.empty()) {
    const DesignComparison& d = o.design;
    Table design{
        fmt::format("Design comparison against {} (band {} / +{} {}; {} gouge and {} excess regions)",
                    o.design_path, number(d.band.low), number(d.band.high), u, d.gouge_regions,
                    d.excess_regions),
        {"kind", "depth", "area (" + u + "^2)", "x", "y", "z", "made by", "nearest move"},
        {}};
    for (const DesignRegion& r : d.regions) {
      std::string made_by;
      for (std::size_t i = 0; i < r.region.sources.size() && i < 3; ++i)
        made_by += (i ? "; " : "") + tag_text(r.region.sources[i].tag);
      design.rows.push_back(
          {raytest::to_string(r.region.kind), number(r.region.worst), number(r.region.area),
           number(r.region.location.x()), number(r.region.location.y()), number(r.region.location.z()),
           made_by.empty() ? "-" : made_by,
           r.nearest_move < 0 ? "-" : fmt::format("move {} (line {})", r.nearest_move, r.nearest_line)});
    }
    result.push_back(design);
  }
  if (!o.generator_skipped.empty()) {
    result.push_back(
        {"Verdict",
         {"check", "holds", "measured", "bound"},
         {{"generator: not run (" + o.generator_skipped + ")", "-", "-", "-"},
          {fmt::format(
               "reference within sqrt(3) * voxel of the exact surface over the {} samples where the surface "
               "is resolvable at this voxel size ({} left out; over all samples: {})",
               o.reference_resolvable_samples, o.unresolvable_samples,
               number(o.reference_to_exact.stats.max_abs)),
           yes_no(o.reference_converges), number(o.reference_resolvable_max), number(o.reference_bound)}}});
    return result;
  }
  result.push_back(
      {"Verdict",
       {"check", "holds", "measured", "bound"},
       {{"generator within tolerance of the exact surface (both ways)", yes_no(o.generator_within_tolerance),
         number(std::max(o.morph_to_exact.stats.max_abs, o.exact_to_morph.max_abs)), number(o.tolerance)},
        {fmt::format(
             "generator and reference agree: two-sided Hausdorff over the {} samples where the surface "
             "is resolvable at this voxel size ({} near acute wedges, thin walls or narrow gaps left out; "
             "over all samples: {})",
             o.agreement_samples, o.unresolvable_samples,
             number(std::max(o.morph_to_reference.stats.max_abs, o.reference_to_morph.stats.max_abs))),
         yes_no(o.sides_agree), number(o.resolvable_hausdorff), number(o.agreement_bound)},
        {"same pieces, volumes within half a voxel times area", yes_no(o.pieces_match),
         o.pieces_below_resolution
             ? fmt::format(
                   "{} vs {} ({} below the voxels' resolution, of both sides, judged by the exact field)",
                   o.morph_pieces.size(), o.reference_pieces.size(), o.pieces_below_resolution)
             : fmt::format("{} vs {}", o.morph_pieces.size(), o.reference_pieces.size()),
         "-"}}});
  if (!o.design_path.empty())
    result.back().rows.push_back(
        {"machined result within the design's band", yes_no(o.design.within_band()),
         fmt::format("{} .. {}", number(o.design.per_point.min), number(o.design.per_point.max)),
         fmt::format("{} .. {}", number(o.design.band.low), number(o.design.band.high))});
  return result;
}

}  // namespace

nlohmann::json stats_to_json(const raytest::DeviationStats& s) {
  return {{"count", s.count},
          {"misses", s.misses},
          {"min", s.min},
          {"max", s.max},
          {"max_abs", s.max_abs},
          {"mean", s.mean},
          {"mean_abs", s.mean_abs},
          {"rms", s.rms},
          {"p50", s.p50},
          {"p90", s.p90},
          {"p99", s.p99},
          {"p99_9", s.p999},
          {"tolerance", s.tolerance},
          {"share_within_tolerance", s.share_within_tolerance},
          {"band", {{"low", s.band.low}, {"high", s.band.high}}},
          {"share_gouge", s.share_gouge},
          {"share_within_band", s.share_within_band},
          {"share_excess", s.share_excess},
          {"histogram", {{"edges", s.histogram.edges}, {"counts", s.histogram.counts}}},
          {"band_histogram",
           {{"edges", s.band_histogram.edges},
            {"counts", s.band_histogram.counts},
            {"underflow", s.band_histogram.underflow},
            {"overflow", s.band_histogram.overflow}}}};
}

nlohmann::json outcome_to_json(const VerifyOutcome& o) {
  nlohmann::json j;
  j["format"] = "morphmill-verify";
  j["format_version"] = 1;  // docs/summary-schema.md; raised only when a field changes meaning or goes
  j["provenance"] = to_json(o.provenance);
  j["units"] = morph::to_string(o.job.units);
  j["sign_convention"] = std::string(raytest::kSignConvention) + " (\"A -> B\": A measured, B the reference)";
  j["job"] = {{"name", o.job.name},
              {"file", o.job.file},
              {"units", morph::to_string(o.job.units)},
              {"moves", o.job.move_count()}};
  j["tolerance"] = o.tolerance;
  j["voxel_size"] = o.voxel_size;
  for (const auto& s : o.stages)
    j["stages"].push_back({{"name", s.name}, {"seconds", s.seconds}, {"peak_rss_mib", s.peak_rss_mib}});
  j["triangles"] = {{"generator", o.morph_triangles}, {"reference", o.reference_triangles}};
  j["reference_active_voxels"] = o.reference_active_voxels;
  auto pieces = [](const std::vector<PieceRecord>& list) {
    nlohmann::json a = nlohmann::json::array();
    for (const auto& p : list) a.push_back({{"volume", p.volume}, {"area", p.area}});
    return a;
  };
  j["pieces"] = {{"generator", pieces(o.morph_pieces)}, {"reference", pieces(o.reference_pieces)}};
  j["closed_manifold"] = {{"generator", o.morph_topology.closed_manifold()},
                          {"reference", o.reference_topology.closed_manifold()}};
  j["deviation"] = {{"generator_to_exact", stats_to_json(o.morph_to_exact.stats)},
                    {"exact_to_generator", stats_to_json(o.exact_to_morph)},
                    {"reference_to_exact", stats_to_json(o.reference_to_exact.stats)},
                    {"generator_to_reference", stats_to_json(o.morph_to_reference.stats)},
                    {"reference_to_generator", stats_to_json(o.reference_to_morph.stats)}};
  j["generator_steps"] = {{"fallbacks", nlohmann::json::object()}, {"exact", nlohmann::json::object()}};
  for (const morph::StepCount& step : o.generator_steps)
    j["generator_steps"][step.fallback ? "fallbacks" : "exact"][step.name] = step.count;
  if (!o.generator_skipped.empty()) {
    j["generator_steps"] = nullptr;
    // Not run is null, never a zero that reads as a measurement.
    j["triangles"]["generator"] = nullptr;
    j["closed_manifold"]["generator"] = nullptr;
    j["pieces"]["generator"] = nullptr;
    for (const char* key :
         {"generator_to_exact", "exact_to_generator", "generator_to_reference", "reference_to_generator"})
      j["deviation"][key] = nullptr;
  }
  for (const auto& w : o.worst)
    j["worst_places"].push_back({{"against", w.against},
                                 {"deviation", w.deviation},
                                 {"position", {w.position.x(), w.position.y(), w.position.z()}},
                                 {"patch_kind", morph::to_string(w.tag.kind)},
                                 {"source", w.tag.source},
                                 {"line", w.tag.line}});
  j["worst_moves"] = nlohmann::json::array();
  for (const auto& g : o.morph_to_exact.groups)
    j["worst_moves"].push_back({{"patch_kind", morph::to_string(g.tag.kind)},
                                {"move", g.tag.source},
                                {"line", g.tag.line},
                                {"stats", stats_to_json(g.stats)}});
  j["regions"] = {{"resolution", o.region_resolution},
                  {"count", {{"exact_surface", o.exact_regions}, {"reference", o.reference_regions}}},
                  {"listed", nlohmann::json::array()}};
  for (const auto& r : o.regions) {
    nlohmann::json sources = nlohmann::json::array();
    for (const auto& s : r.region.sources)
      sources.push_back({{"patch_kind", morph::to_string(s.tag.kind)},
                         {"move", s.tag.source},
                         {"line", s.tag.line},
                         {"worst", s.worst}});
    j["regions"]["listed"].push_back(
        {{"against", r.against},
         {"band", {{"low", r.band.low}, {"high", r.band.high}}},
         {"kind", raytest::to_string(r.region.kind)},
         {"worst", r.region.worst},
         {"area", r.region.area},
         {"location", {r.region.location.x(), r.region.location.y(), r.region.location.z()}},
         {"made_by", sources}});
  }
  if (!o.design_path.empty()) {
    j["design"] = comparison_to_json(o.design, o.job);
    j["design"]["path"] = o.design_path;
  }
  for (const auto& [n, tool] : o.job.tools)
    j["tools"].push_back({{"number", n},
                          {"type", morph::to_string(tool.type)},
                          {"shape", morph::describe(tool)},
                          {"diameter", 2.0 * tool.radius},
                          {"length_offset", tool.length_offset}});
  if (!o.generator_skipped.empty())
    j["reference_check"] = {{"generator_skipped", o.generator_skipped},
                            {"reference_only_requested", true},  // the one way it is skipped
                            {"resolvable_max", o.reference_resolvable_max},
                            {"resolvable_samples", o.reference_resolvable_samples},
                            {"bound", o.reference_bound},
                            {"converges", o.reference_converges}};
  j["verdict"] = {{"holds", o.verdict()},
                  {"generator_within_tolerance", o.generator_within_tolerance},
                  {"sides_agree", o.sides_agree},
                  {"agreement_bound", o.agreement_bound},
                  {"resolvable_hausdorff", o.resolvable_hausdorff},
                  {"agreement_samples", o.agreement_samples},
                  {"unresolvable_samples", o.unresolvable_samples},
                  {"pieces_match", o.pieces_match},
                  {"pieces_below_resolution", o.pieces_below_resolution},
                  {"design_within_band", o.design_within_band()}};
  return j;
}

void write_reports(const VerifyOutcome& o, const std::string& out_dir,
                   const std::vector<std::pair<std::string, std::string>>& pictures,
                   const std::string& view3d_html) {
  const fs::path dir(out_dir);
  std::vector<Table> all = tables(o);
  all.push_back(provenance_table(o.provenance));
  const std::string verdict =
      !o.generator_skipped.empty()
          ? std::string(o.verdict() ? "HOLDS for the reference alone" : "NOT VERIFIED") +
                " (generator not run: " + o.generator_skipped + "; reference against the exact surface " +
                (o.reference_converges ? "holds" : "DOES NOT HOLD") + ")"
          : std::string(o.verdict() ? "HOLDS" : "DOES NOT HOLD");
  {
    AtomicOutput md(dir / "report.md");
    md << "# MorphMill verification: " << o.job.name << "\n\n**Verdict: " << verdict << "**\n\n"
       << "Sign of every deviation: " << raytest::kSignConvention << ".\n\n";
    for (const auto& t : all) md << markdown(t);
    md << "### Pictures\n\n";
    for (const auto& [title, file] : pictures) md << "![" << title << "](" << file << ")\n\n";
    md.commit();
  }
  AtomicOutput page(dir / "report.html");
  page << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<title>MorphMill verification: "
       << html_escape(o.job.name) << "</title>\n<style>\n"
       << "body{font-family:sans-serif;margin:2em;max-width:1100px;color:#222}\n"
       << "table{border-collapse:collapse;margin-bottom:1em}td,th{border:1px solid #bbb;padding:3px 8px;"
          "text-align:right}th{background:#eee}td:first-child{text-align:left}\n"
       << ".verdict{font-size:1.4em;padding:.4em;border-radius:4px}.holds{background:#d4f4d4}"
          ".fails{background:#f8d0d0}\nfigure{display:inline-block;margin:0 1em 1em 0}"
          "figcaption{text-align:center}\n</style></head>\n<body>\n<h1>MorphMill verification: "
       << html_escape(o.job.name) << "</h1>\n<p class=\"verdict " << (o.verdict() ? "holds" : "fails")
       << "\">Verdict: " << verdict
       << "</p>\n<p class=\"sign\">Sign of every deviation: " << html_escape(raytest::kSignConvention)
       << ".</p>\n";
  for (const auto& t : all) page << html(t);
  page << view3d_html;
  page << "<h3>Pictures</h3>\n";
  for (const auto& [title, file] : pictures) {
    page << "<figure><img alt=\"" << html_escape(title) << "\" src=\"data:image/png;base64,"
         << base64(read_file_bytes(dir / file)) << "\"><figcaption>" << html_escape(title)
         << "</figcaption></figure>\n";
  }
  // Lets a browser test read back how many pictures the browser decoded.
  page << "<script>window.addEventListener('load',function(){var i=document.images,n=0;"
          "for(var k=0;k<i.length;k++){if(i[k].complete&&i[k].naturalWidth>0)n++;}"
          "document.body.setAttribute('data-images-loaded',n+'/'+i.length);});</script>\n</body></html>\n";
  page.commit();
}

}  // namespace morphmill
