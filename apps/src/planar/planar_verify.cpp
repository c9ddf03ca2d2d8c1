// SPDX-License-Identifier: Apache-2.0
#include "planar/planar_verify.h"

#include <fmt/format.h>
#include <morph/exceptions.h>
#include <planar_ref/clipper_reference.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "io/atomic_output.h"
#include "io/provenance.h"

namespace morphmill {

namespace {

using morph::planar::Region;
using nlohmann::json;

/// Blue (0) through green and yellow to red (1).
std::string ramp(double x) {
  x = std::clamp(x, 0.0, 1.0);
  static const double stops[5][3] = {
      {49, 54, 149}, {69, 173, 104}, {171, 221, 64}, {253, 174, 57}, {215, 25, 28}};
  const double s = x * 4.0;
  const int i = std::min(3, static_cast<int>(s));
  const double f = s - i;
  int rgb[3];
  for (int k = 0; k < 3; ++k)
    rgb[k] = static_cast<int>(std::lround(stops[i][k] + f * (stops[i + 1][k] - stops[i][k])));
  return fmt::format("#{:02x}{:02x}{:02x}", rgb[0], rgb[1], rgb[2]);
}

std::string loops_path(const Region& region) {
  std::string d;
  for (const auto& loop : region.loops) {
    if (loop.curves.empty()) continue;
    d += fmt::format("M{:.9g},{:.9g}", loop.curves.front().start.x(), loop.curves.front().start.y());
    for (const auto& c : loop.curves) {
      const int parts = c.is_arc() ? std::max(1, static_cast<int>(std::ceil(std::abs(c.sweep) / 0.05))) : 1;
      for (int k = 1; k <= parts; ++k) {
        const auto p = morph::planar::point_at(c, static_cast<double>(k) / parts);
        d += fmt::format(" L{:.9g},{:.9g}", p.x(), p.y());
      }
    }
    d += " Z";
  }
  return d;
}

json deviation_json(const morph::planar::DirectedDeviation& d) {
  return {{"max_outside", d.max_outside},
          {"max_inside", d.max_inside},
          {"mean_abs", d.mean_abs},
          {"samples", d.samples.size()},
          {"worst", {{"x", d.worst.point.x()}, {"y", d.worst.point.y()}, {"distance", d.worst.distance}}}};
}

}  // namespace

void write_deviation_svg(const Region& measured, const morph::planar::DirectedDeviation& deviation,
                         const Region& other, double colour_max, const std::string& title,
                         const std::string& path) {
  morph::planar::Box2 box = morph::planar::bounds(measured);
  box.extend(morph::planar::bounds(other));
  if (box.isEmpty()) box = morph::planar::Box2(morph::planar::Vec2(0, 0), morph::planar::Vec2(1, 1));
  const double size = std::max(box.sizes().maxCoeff(), 1e-9), margin = 0.08 * size, dot = size / 500.0;
  const double width = box.sizes().x() + 2 * margin, height = box.sizes().y() + 2 * margin;
  AtomicOutput out(path);
  out << fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"{:.9g} {:.9g} {:.9g} {:.9g}\" width=\"800\" "
      "height=\"{}\">\n<title>{}</title>\n",
      box.min().x() - margin, -box.max().y() - margin, width, height, static_cast<int>(800 * height / width),
      title);
  out << fmt::format("<rect x=\"{:.9g}\" y=\"{:.9g}\" width=\"{:.9g}\" height=\"{:.9g}\" fill=\"white\"/>\n",
                     box.min().x() - margin, -box.max().y() - margin, width, height);
  out << "<g transform=\"scale(1,-1)\">\n";
  out << fmt::format(
      "<path d=\"{}\" fill=\"#f2f2f2\" stroke=\"#999999\" stroke-width=\"{:.6g}\" "
      "fill-rule=\"evenodd\"/>\n",
      loops_path(other), 0.5 * dot);
  for (const auto& s : deviation.samples)
    out << fmt::format("<circle cx=\"{:.9g}\" cy=\"{:.9g}\" r=\"{:.6g}\" fill=\"{}\"/>\n", s.point.x(),
                       s.point.y(), dot, ramp(colour_max > 0.0 ? std::abs(s.distance) / colour_max : 0.0));
  out << "</g>\n";
  // Legend in screen coordinates along the bottom margin.
  const double lx = box.min().x(), ly = -box.min().y() + 0.35 * margin, lw = 0.5 * width;
  for (int i = 0; i < 20; ++i)
    out << fmt::format("<rect x=\"{:.9g}\" y=\"{:.9g}\" width=\"{:.9g}\" height=\"{:.9g}\" fill=\"{}\"/>\n",
                       lx + lw * i / 20.0, ly, lw / 20.0 * 1.02, 0.25 * margin, ramp(i / 19.0));
  out << fmt::format(
      "<text x=\"{:.9g}\" y=\"{:.9g}\" font-size=\"{:.6g}\" font-family=\"sans-serif\">0 .. {:.3g} "
      "(|distance|, job units)</text>\n",
      lx + lw * 1.03, ly + 0.22 * margin, 0.3 * margin, colour_max);
  out << "</svg>\n";
  out.commit();
}

json verify2d_summary_json(const Verify2dOutcome& o) {
  json report;
  report["format"] = "morphmill-verify2d";
  report["format_version"] = 1;
  report["units"] = morph::to_string(o.job.units);
  report["provenance"] = to_json(o.provenance);
  report["job"] = o.job.name;
  report["file"] = o.job.file;
  report["radius"] = o.job.radius;
  report["tolerance"] = o.tolerance;
  report["moves"] = o.job.moves.size();
  report["exact"] = {{"area", morph::planar::area(o.exact.region)},
                     {"perimeter", morph::planar::perimeter(o.exact.region)},
                     {"pieces", o.exact.region.pieces.size()},
                     {"holes", morph::planar::hole_count(o.exact.region)},
                     {"curves_kept", o.exact.stats.pieces_kept},
                     {"intersections", o.exact.stats.intersections},
                     {"seconds", o.exact.stats.seconds}};
  report["dilation"] = {{"area", morph::planar::area(o.dilation.region)},
                        {"pieces", o.dilation.region.pieces.size()}};
  report["classical"] = {{"area", morph::planar::area(o.classical.region)},
                         {"pieces", o.classical.region.pieces.size()}};
  report["reference"] = {{"area", morph::planar::area(o.reference)},
                         {"pieces", o.reference.pieces.size()},
                         {"holes", morph::planar::hole_count(o.reference)}};
  report["deviation"] = {{"hausdorff", o.deviation.hausdorff()},
                         {"exact_to_reference", deviation_json(o.deviation.a_to_b)},
                         {"reference_to_exact", deviation_json(o.deviation.b_to_a)}};
  report["convergence"] = json::array();
  for (const ConvergenceRow& row : o.convergence)
    report["convergence"].push_back({{"chord_tolerance", row.chord_tolerance},
                                     {"hausdorff", row.hausdorff},
                                     {"area_difference", row.area_difference},
                                     {"reference_vertices", row.reference_vertices},
                                     {"reference_seconds", row.reference_seconds}});
  report["verdict"] = {
      {"pieces_match", o.pieces_match}, {"within_bound", o.within_bound}, {"holds", o.verdict()}};
  return report;
}

Verify2dOutcome run_verify2d(const Verify2dOptions& options) {
  Verify2dOutcome o;
  o.job = load_planar_job(options.job_path);
  o.tolerance = options.tolerance > 0.0 ? options.tolerance : o.job.tolerance;
  o.provenance = make_provenance({options.job_path}, {{"command", "verify2d"}, {"tolerance", o.tolerance}},
                                 morph::to_string(o.job.units));
  std::filesystem::create_directories(options.out_dir);
  morph::planar::PlanarOptions planar;
  planar.progress = options.progress;
  o.exact = morph::planar::erode(o.job.stock, o.job.moves, o.job.radius, planar);
  o.dilation = morph::planar::dilate(o.job.moves, o.job.radius, planar);
  o.classical = morph::planar::classical_erosion(o.job.stock, o.job.radius, planar);
  for (const double factor : {10.0, 1.0, 0.1}) {
    planar_ref::ReferenceOptions ref_options;
    ref_options.chord_tolerance = factor * o.tolerance;
    const auto reference = planar_ref::reference_erosion(o.job.stock, o.job.moves, o.job.radius, ref_options);
    const auto deviation = morph::planar::planar_deviation(o.exact.region, reference.region);
    o.convergence.push_back({ref_options.chord_tolerance, deviation.hausdorff(),
                             morph::planar::area(reference.region) - morph::planar::area(o.exact.region),
                             reference.vertices, reference.seconds});
    if (factor == 1.0) {
      o.reference = reference.region;
      o.deviation = deviation;
    }
  }
  o.pieces_match = o.exact.region.pieces.size() == o.reference.pieces.size() &&
                   morph::planar::hole_count(o.exact.region) == morph::planar::hole_count(o.reference);
  o.within_bound = o.deviation.hausdorff() <= 2.0 * o.tolerance;

  const std::string dir = options.out_dir + "/";
  PlanarDrawing drawing;
  drawing.stock = &o.job.stock;
  drawing.result = &o.exact.region;
  drawing.moves = &o.job.moves;
  drawing.title = o.job.name + ": X \\ (T + B)";
  write_planar_result(drawing, dir + "result.svg");
  write_planar_result(drawing, dir + "result.dxf");
  write_planar_result(drawing, dir + "result.json");
  PlanarDrawing dilation;
  dilation.dilation = &o.dilation.region;
  dilation.stock = &o.job.stock;
  dilation.moves = &o.job.moves;
  dilation.title = o.job.name + ": T + B";
  write_planar_svg(dilation, dir + "dilation.svg");
  PlanarDrawing classical;
  classical.stock = &o.job.stock;
  classical.result = &o.classical.region;
  classical.title = o.job.name + ": X - B (classical erosion)";
  write_planar_svg(classical, dir + "classical.svg");
  PlanarDrawing reference;
  reference.stock = &o.job.stock;
  reference.result = &o.reference;
  reference.title = o.job.name + ": Clipper reference";
  write_planar_svg(reference, dir + "reference.svg");
  write_deviation_svg(
      o.exact.region, o.deviation.a_to_b, o.reference, std::max(o.deviation.hausdorff(), 1e-300),
      o.job.name + ": exact boundary coloured by its distance to the reference", dir + "deviation.svg");

  morph::write_file_atomically(dir + "report.json", verify2d_summary_json(o).dump(1) + "\n");

  AtomicOutput md(dir + "report.md");
  md << "# verify2d " << o.job.name << "\n\n"
     << fmt::format("Disc radius {}, {} moves, reference chord tolerance {}.\n\n", o.job.radius,
                    o.job.moves.size(), o.tolerance)
     << "| | area | perimeter | pieces | holes |\n|---|---|---|---|---|\n"
     << fmt::format("| exact | {:.12g} | {:.12g} | {} | {} |\n", morph::planar::area(o.exact.region),
                    morph::planar::perimeter(o.exact.region), o.exact.region.pieces.size(),
                    morph::planar::hole_count(o.exact.region))
     << fmt::format("| Clipper | {:.12g} | {:.12g} | {} | {} |\n\n", morph::planar::area(o.reference),
                    morph::planar::perimeter(o.reference), o.reference.pieces.size(),
                    morph::planar::hole_count(o.reference))
     << fmt::format(
            "Hausdorff distance between the boundaries: {:.3g} (exact -> reference: {:.3g} outside, {:.3g} "
            "inside; reference -> exact: {:.3g} outside, {:.3g} inside).\n\n",
            o.deviation.hausdorff(), o.deviation.a_to_b.max_outside, o.deviation.a_to_b.max_inside,
            o.deviation.b_to_a.max_outside, o.deviation.b_to_a.max_inside)
     << "| chord tolerance | Hausdorff | area difference | reference vertices |\n|---|---|---|---|\n";
  for (const ConvergenceRow& row : o.convergence)
    md << fmt::format("| {:.3g} | {:.3g} | {:.3g} | {} |\n", row.chord_tolerance, row.hausdorff,
                      row.area_difference, row.reference_vertices);
  md << "\nVerdict: " << (o.verdict() ? "holds" : "DOES NOT HOLD")
     << " (same pieces and holes, Hausdorff <= 2 x tolerance).\n\n"
     << "Pictures: result.svg, dilation.svg, classical.svg, reference.svg, deviation.svg.\n";
  md.commit();
  return o;
}

}  // namespace morphmill
