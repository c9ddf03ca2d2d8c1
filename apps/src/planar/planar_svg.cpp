// SPDX-License-Identifier: Apache-2.0
// SVG for the planar model: reading outlines and trajectories from <path> and the basic shapes,
// writing pictures whose arcs stay exact (the path 'A' command). SVG draws y downwards; the
// planar model's y goes up, so y is flipped both ways.
#include <fmt/format.h>
#include <morph/exceptions.h>
#include <morphmill/planar_io.h>

#include <cctype>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "io/atomic_output.h"

namespace morphmill {

namespace {

using morph::InputError;
using morph::planar::Curve;
using morph::planar::Vec2;

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw morph::IoError(path + ": cannot open the SVG file");
  std::ostringstream out;
  out << in.rdbuf();
  return out.str();
}

Curve flipped(Curve c) {
  c.start.y() = -c.start.y();
  c.end.y() = -c.end.y();
  c.center.y() = -c.center.y();
  c.sweep = -c.sweep;
  return c;
}

/// One SVG element: its name, attributes and line.
struct Element {
  std::string name;
  std::map<std::string, std::string> attributes;
  int line = 0;
};

/// Reads the numbers and commands of a path's d attribute.
class PathScanner {
 public:
  explicit PathScanner(const std::string& d) : d_(d) {}
  void skip() {
    while (pos_ < d_.size() && (std::isspace(static_cast<unsigned char>(d_[pos_])) || d_[pos_] == ','))
      ++pos_;
  }
  bool done() {
    skip();
    return pos_ >= d_.size();
  }
  bool at_number() {
    skip();
    return pos_ < d_.size() && (std::isdigit(static_cast<unsigned char>(d_[pos_])) || d_[pos_] == '-' ||
                                d_[pos_] == '+' || d_[pos_] == '.');
  }
  char command() {
    skip();
    return d_[pos_++];
  }
  double number(const std::string& what) {
    skip();
    const char* begin = d_.c_str() + pos_;
    char* end = nullptr;
    const double x = std::strtod(begin, &end);
    if (end == begin || !std::isfinite(x))
      throw InputError(what + ": expected a number at '" + d_.substr(pos_, 12) + "'");
    pos_ += static_cast<std::size_t>(end - begin);
    return x;
  }
  /// Arc flags may be written without separators ("a1 1 0 01 2 2").
  bool flag(const std::string& what) {
    skip();
    if (pos_ < d_.size() && (d_[pos_] == '0' || d_[pos_] == '1')) return d_[pos_++] == '1';
    throw InputError(what + ": expected an arc flag 0 or 1");
  }

 private:
  const std::string& d_;
  std::size_t pos_ = 0;
};

/// The circular arc of SVG's endpoint parametrisation (rx == ry), in SVG's own coordinates.
Curve svg_arc(const Vec2& a, const Vec2& b, double r, bool large, bool positive, const std::string& what) {
  if (a == b) return morph::planar::make_segment(a, b);  // SVG omits such arcs
  if (r == 0.0) return morph::planar::make_segment(a, b);
  const Vec2 half = 0.5 * (a - b);
  const double h2 = half.squaredNorm();
  r = std::max(r, std::sqrt(h2));  // too small a radius is scaled up (SVG implementation notes F.6.6)
  const double k = std::sqrt(std::max(0.0, (r * r - h2) / h2)) * (large != positive ? 1.0 : -1.0);
  const Vec2 center = 0.5 * (a + b) + k * Vec2(half.y(), -half.x());
  (void)what;
  return morph::planar::make_arc_between(center, a, b, positive);
}

void parse_path(const Element& e, const std::string& where, PlanarShapes& shapes) {
  auto it = e.attributes.find("d");
  if (it == e.attributes.end()) throw InputError(where + ": <path> without a 'd' attribute");
  PathScanner scan(it->second);
  std::vector<Curve> current;
  Vec2 at(0, 0), start(0, 0);
  char command = 0;
  auto finish = [&](bool closed) {
    if (current.empty()) return;
    if (closed) {
      morph::planar::Loop loop;
      for (const Curve& c : current)
        if (c.is_arc() || c.start != c.end) loop.curves.push_back(c);
      if (!loop.curves.empty()) shapes.closed.push_back(loop);
    } else
      shapes.open.push_back(current);
    current.clear();
  };
  auto add = [&](const Curve& c) {
    Curve f = flipped(c);
    f.from.line = e.line;
    current.push_back(f);  // a zero-length piece of an open path is a plunge
    at = c.end;
  };
  while (!scan.done()) {
    if (!scan.at_number()) command = scan.command();
    if (command == 0) throw InputError(where + ": the path data must start with a command");
    const bool relative = std::islower(static_cast<unsigned char>(command)) != 0;
    const Vec2 base = relative ? at : Vec2(0, 0);
    const std::string what = where + ": path command '" + std::string(1, command) + "'";
    switch (std::toupper(static_cast<unsigned char>(command))) {
      case 'M': {
        finish(false);
        const double x = scan.number(what), y = scan.number(what);
        at = start = base + Vec2(x, y);
        command = relative ? 'l' : 'L';  // further pairs are lines
        break;
      }
      case 'L': {
        const double x = scan.number(what), y = scan.number(what);
        add(morph::planar::make_segment(at, base + Vec2(x, y)));
        break;
      }
      case 'H': {
        const double x = scan.number(what);
        add(morph::planar::make_segment(at, Vec2(relative ? at.x() + x : x, at.y())));
        break;
      }
      case 'V': {
        const double y = scan.number(what);
        add(morph::planar::make_segment(at, Vec2(at.x(), relative ? at.y() + y : y)));
        break;
      }
      case 'A': {
        const double rx = scan.number(what), ry = scan.number(what);
        scan.number(what);  // x-axis rotation: irrelevant for a circle
        const bool large = scan.flag(what), positive = scan.flag(what);
        const double x = scan.number(what), y = scan.number(what);
        if (std::abs(std::abs(rx) - std::abs(ry)) > 1e-9 * std::max(std::abs(rx), std::abs(ry)))
          throw InputError(what + ": elliptical arcs (rx " + fmt::format("{}", rx) + " != ry " +
                           fmt::format("{}", ry) + ") are not supported, only circular ones");
        add(svg_arc(at, base + Vec2(x, y), std::abs(rx), large, positive, what));
        break;
      }
      case 'Z': {
        if ((at - start).norm() > 0.0) add(morph::planar::make_segment(at, start));
        at = start;
        finish(true);
        command = 0;
        break;
      }
      default:
        throw InputError(what + " is not supported (M, L, H, V, A, Z are; convert curves to lines or arcs)");
    }
  }
  finish(false);
}

double attribute_number(const Element& e, const std::string& name, const std::string& where,
                        double fallback = NAN) {
  auto it = e.attributes.find(name);
  if (it == e.attributes.end()) {
    if (std::isnan(fallback)) throw InputError(where + ": missing attribute '" + name + "'");
    return fallback;
  }
  char* end = nullptr;
  const double x = std::strtod(it->second.c_str(), &end);
  if (end == it->second.c_str() || !std::isfinite(x))
    throw InputError(where + ": attribute '" + name + "' is not a number: '" + it->second + "'");
  return x;
}

std::vector<Curve> point_chain(const Element& e, const std::string& where, bool closed) {
  auto it = e.attributes.find("points");
  if (it == e.attributes.end()) throw InputError(where + ": missing attribute 'points'");
  PathScanner scan(it->second);
  std::vector<Vec2> points;
  while (!scan.done()) {
    const double x = scan.number(where), y = scan.number(where);
    points.emplace_back(x, -y);
  }
  if (points.size() < 2) throw InputError(where + ": needs at least two points");
  std::vector<Curve> chain;
  const std::size_t n = closed ? points.size() : points.size() - 1;
  for (std::size_t i = 0; i < n; ++i)
    chain.push_back(morph::planar::make_segment(points[i], points[(i + 1) % points.size()], {{}, 0, e.line}));
  return chain;
}

std::vector<Element> scan_elements(const std::string& text, const std::string& path) {
  std::vector<Element> out;
  std::size_t pos = 0;
  int line = 1;
  std::size_t counted = 0;
  while ((pos = text.find('<', pos)) != std::string::npos) {
    for (; counted < pos; ++counted) line += text[counted] == '\n';
    if (text.compare(pos, 4, "<!--") == 0) {
      pos = text.find("-->", pos);
      if (pos == std::string::npos) break;
      continue;
    }
    const std::size_t end = text.find('>', pos);
    if (end == std::string::npos) throw InputError(fmt::format("{}:{}: unterminated element", path, line));
    Element e;
    e.line = line;
    std::size_t i = pos + 1;
    while (i < end && !std::isspace(static_cast<unsigned char>(text[i])) && text[i] != '/')
      e.name += text[i++];
    while (i < end) {
      while (i < end && (std::isspace(static_cast<unsigned char>(text[i])) || text[i] == '/')) ++i;
      std::string name;
      while (i < end && text[i] != '=' && !std::isspace(static_cast<unsigned char>(text[i])))
        name += text[i++];
      while (i < end && text[i] != '=' && std::isspace(static_cast<unsigned char>(text[i]))) ++i;
      if (i >= end || text[i] != '=') break;
      ++i;
      while (i < end && std::isspace(static_cast<unsigned char>(text[i]))) ++i;
      const char quote = text[i];
      if (quote != '"' && quote != '\'') break;
      const std::size_t close = text.find(quote, i + 1);
      if (close == std::string::npos) break;
      e.attributes[name] = text.substr(i + 1, close - i - 1);
      i = close + 1;
    }
    out.push_back(std::move(e));
    pos = end + 1;
  }
  return out;
}

}  // namespace

PlanarShapes read_svg_shapes(const std::string& path) {
  const std::string text = read_text(path);
  PlanarShapes shapes;
  for (const Element& e : scan_elements(text, path)) {
    const std::string where = fmt::format("{}:{}: <{}>", path, e.line, e.name);
    static const char* shape_names[] = {"path",     "rect", "circle",  "polygon",
                                        "polyline", "line", "ellipse", "g"};
    bool shape = false;
    for (const char* name : shape_names) shape = shape || e.name == name;
    if (!shape) continue;
    if (e.attributes.count("transform"))
      throw InputError(where + ": transforms are not supported (apply them to the coordinates first)");
    if (e.name == "g") continue;
    if (e.name == "path") {
      parse_path(e, where, shapes);
    } else if (e.name == "rect") {
      const double x = attribute_number(e, "x", where, 0.0), y = attribute_number(e, "y", where, 0.0);
      const double w = attribute_number(e, "width", where), h = attribute_number(e, "height", where);
      if (attribute_number(e, "rx", where, 0.0) != 0.0 || attribute_number(e, "ry", where, 0.0) != 0.0)
        throw InputError(where + ": rounded rectangles are not supported (draw them as a path with arcs)");
      if (!(w > 0.0 && h > 0.0)) throw InputError(where + ": width and height must be positive");
      morph::planar::Loop loop;
      const Vec2 p[4] = {{x, -y}, {x + w, -y}, {x + w, -(y + h)}, {x, -(y + h)}};
      for (int i = 0; i < 4; ++i)
        loop.curves.push_back(morph::planar::make_segment(p[i], p[(i + 1) % 4], {{}, 0, e.line}));
      shapes.closed.push_back(loop);
    } else if (e.name == "circle") {
      const Vec2 c(attribute_number(e, "cx", where, 0.0), -attribute_number(e, "cy", where, 0.0));
      const double r = attribute_number(e, "r", where);
      if (!(r > 0.0)) throw InputError(where + ": the radius must be positive");
      morph::planar::Loop loop;
      loop.curves.push_back(morph::planar::make_arc(c, r, 0.0, M_PI, {{}, 0, e.line}));
      loop.curves.push_back(morph::planar::make_arc(c, r, M_PI, M_PI, {{}, 0, e.line}));
      loop.curves[1].start = loop.curves[0].end;
      loop.curves[1].end = loop.curves[0].start;
      shapes.closed.push_back(loop);
    } else if (e.name == "polygon") {
      shapes.closed.push_back(morph::planar::Loop{point_chain(e, where, true)});
    } else if (e.name == "polyline") {
      shapes.open.push_back(point_chain(e, where, false));
    } else if (e.name == "line") {
      const Vec2 a(attribute_number(e, "x1", where, 0.0), -attribute_number(e, "y1", where, 0.0));
      const Vec2 b(attribute_number(e, "x2", where, 0.0), -attribute_number(e, "y2", where, 0.0));
      shapes.open.push_back({morph::planar::make_segment(a, b, {{}, 0, e.line})});
    } else {
      throw InputError(where + ": ellipses are not supported (only circular arcs)");
    }
  }
  if (shapes.closed.empty() && shapes.open.empty()) throw InputError(path + ": no path or shape found");
  return shapes;
}

// ---- Writing ----

namespace {

/// Path data in SVG's frame (y flipped, so a counter-clockwise arc has sweep flag 0): the picture
/// reads back through read_svg_shapes as the same curves.
std::string move_to(const Vec2& p) {
  return fmt::format(" M{:.10g},{:.10g}", p.x(), 0.0 - p.y());
}

std::string draw(const Curve& c) {
  if (!c.is_arc()) return fmt::format(" L{:.10g},{:.10g}", c.end.x(), 0.0 - c.end.y());
  // SVG cannot draw a full circle in one arc: two halves.
  std::string d;
  const int parts = std::abs(c.sweep) > 1.5 * M_PI ? 2 : 1;
  for (int k = 1; k <= parts; ++k) {
    const Vec2 p = k == parts ? c.end : morph::planar::point_at(c, static_cast<double>(k) / parts);
    d += fmt::format(" A{:.10g},{:.10g} 0 {} {} {:.10g},{:.10g}", c.radius, c.radius,
                     std::abs(c.sweep) / parts > M_PI ? 1 : 0, c.sweep > 0.0 ? 0 : 1, p.x(), 0.0 - p.y());
  }
  return d;
}

std::string svg_path(const morph::planar::Region& region) {
  std::string d;
  for (const auto& loop : region.loops) {
    if (loop.curves.empty()) continue;
    d += move_to(loop.curves.front().start);
    for (const Curve& c : loop.curves) d += draw(c);
    d += " Z";
  }
  return d;
}

std::string trajectory_path(const morph::planar::Trajectory& moves) {
  std::string d;
  Vec2 at(NAN, NAN);
  for (const Curve& c : moves) {
    if (!(c.start == at)) d += move_to(c.start);
    d += c.is_arc() || c.start != c.end ? draw(c) : fmt::format(" l0,0");
    at = c.end;
  }
  return d;
}

}  // namespace

void write_planar_svg(const PlanarDrawing& drawing, const std::string& path) {
  morph::planar::Box2 box;
  for (const auto* region : {drawing.stock, drawing.result, drawing.dilation})
    if (region) box.extend(morph::planar::bounds(*region));
  if (drawing.moves)
    for (const Curve& c : *drawing.moves) box.extend(morph::planar::bounds(c));
  if (box.isEmpty()) box = morph::planar::Box2(Vec2(0, 0), Vec2(1, 1));
  const double size = std::max(box.sizes().maxCoeff(), 1e-9);
  const double margin = 0.05 * size, stroke = size / 600.0;
  const double width = box.sizes().x() + 2 * margin, height = box.sizes().y() + 2 * margin;
  AtomicOutput out(path);
  out << fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"{:.9g} {:.9g} {:.9g} {:.9g}\" width=\"{}\" "
      "height=\"{}\">\n",
      box.min().x() - margin, -box.max().y() - margin, width, height, 800,
      static_cast<int>(800 * height / width));
  if (!drawing.title.empty()) out << "<title>" << drawing.title << "</title>\n";
  out << "<g stroke-linejoin=\"round\" stroke-linecap=\"round\">\n";
  if (drawing.stock)
    out << fmt::format(
        "<path id=\"stock\" d=\"{}\" fill=\"#eeeeee\" stroke=\"#888888\" stroke-width=\"{:.6g}\" "
        "stroke-dasharray=\"{:.6g}\" fill-rule=\"evenodd\"/>\n",
        svg_path(*drawing.stock), stroke, 4 * stroke);
  if (drawing.result)
    out << fmt::format(
        "<path id=\"result\" d=\"{}\" fill=\"#7fa7d9\" stroke=\"#1f4e8c\" stroke-width=\"{:.6g}\" "
        "fill-rule=\"evenodd\"/>\n",
        svg_path(*drawing.result), 1.5 * stroke);
  if (drawing.dilation)
    out << fmt::format(
        "<path id=\"dilation\" d=\"{}\" fill=\"#d9534f\" fill-opacity=\"0.25\" stroke=\"#b52b27\" "
        "stroke-width=\"{:.6g}\" fill-rule=\"nonzero\"/>\n",
        svg_path(*drawing.dilation), stroke);
  if (drawing.moves)
    out << fmt::format(
        "<path id=\"trajectory\" d=\"{}\" fill=\"none\" stroke=\"black\" stroke-width=\"{:.6g}\" "
        "stroke-dasharray=\"{:.6g}\"/>\n",
        trajectory_path(*drawing.moves), stroke, 3 * stroke);
  out << "</g>\n</svg>\n";
  out.commit();
}

}  // namespace morphmill
