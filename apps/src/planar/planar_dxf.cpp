// SPDX-License-Identifier: Apache-2.0
// DXF for the planar model: LINE, ARC, CIRCLE and LWPOLYLINE (with bulges) read from the ENTITIES
// section, open pieces chained end to end; results written as R12 LINE and ARC entities.
#include <fmt/format.h>
#include <morph/exceptions.h>
#include <morphmill/planar_io.h>

#include <cmath>
#include <fstream>
#include <map>

#include "io/atomic_output.h"

namespace morphmill {

namespace {

using morph::InputError;
using morph::planar::Curve;
using morph::planar::Loop;
using morph::planar::Vec2;

struct Group {
  int code = 0;
  std::string value;
  int line = 0;
};

std::vector<Group> read_groups(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw morph::IoError(path + ": cannot open the DXF file");
  std::vector<Group> groups;
  std::string code, value;
  int line = 0;
  while (std::getline(in, code)) {
    ++line;
    if (!std::getline(in, value))
      throw InputError(fmt::format("{}:{}: group code without a value", path, line));
    ++line;
    if (!value.empty() && value.back() == '\r') value.pop_back();
    Group g;
    g.line = line - 1;
    char* end = nullptr;
    g.code = static_cast<int>(std::strtol(code.c_str(), &end, 10));
    if (end == code.c_str())
      throw InputError(fmt::format("{}:{}: expected a group code, got '{}'", path, line - 1, code));
    const std::size_t first = value.find_first_not_of(' ');
    g.value = first == std::string::npos ? "" : value.substr(first);
    groups.push_back(std::move(g));
  }
  return groups;
}

/// One entity's groups.
struct Entity {
  std::string type;
  int line = 0;
  std::vector<Group> groups;

  double number(int code, const std::string& path, double fallback = NAN) const {
    for (const Group& g : groups)
      if (g.code == code) return parse(g, path);
    if (std::isnan(fallback))
      throw InputError(fmt::format("{}:{}: {} without group code {}", path, line, type, code));
    return fallback;
  }
  static double parse(const Group& g, const std::string& path) {
    char* end = nullptr;
    const double x = std::strtod(g.value.c_str(), &end);
    if (end == g.value.c_str() || !std::isfinite(x))
      throw InputError(fmt::format("{}:{}: expected a number, got '{}'", path, g.line, g.value));
    return x;
  }
};

/// Object coordinates with extrusion (0, 0, -1) are mirrored in x.
struct Ocs {
  bool mirrored = false;
  Vec2 point(double x, double y) const { return Vec2(mirrored ? -x : x, y); }
};

Curve arc_entity(const Entity& e, const std::string& path, const Ocs& ocs) {
  const Vec2 c = ocs.point(e.number(10, path), e.number(20, path));
  const double r = e.number(40, path);
  if (!(r > 0.0)) throw InputError(fmt::format("{}:{}: {} with radius {}", path, e.line, e.type, r));
  double a0 = e.number(50, path) * M_PI / 180.0, a1 = e.number(51, path) * M_PI / 180.0;
  double sweep = std::fmod(a1 - a0, 2.0 * M_PI);
  if (sweep <= 0.0) sweep += 2.0 * M_PI;
  if (ocs.mirrored) {
    a0 = M_PI - a0;
    sweep = -sweep;
  }
  return morph::planar::make_arc(c, r, a0, sweep, {{}, 0, e.line});
}

/// Chains open curves whose ends meet (within gap) into longer chains; closed chains become loops.
void chain(std::vector<Curve> pieces, double gap, PlanarShapes& shapes) {
  std::vector<char> used(pieces.size(), 0);
  for (std::size_t s = 0; s < pieces.size(); ++s) {
    if (used[s]) continue;
    used[s] = 1;
    std::vector<Curve> chain{pieces[s]};
    for (bool grew = true; grew;) {
      grew = false;
      for (std::size_t i = 0; i < pieces.size(); ++i) {
        if (used[i]) continue;
        // Drawings round their coordinates: a joined end takes its neighbour's exact value.
        if ((pieces[i].start - chain.back().end).norm() <= gap) {
          chain.push_back(pieces[i]);
          chain.back().start = chain[chain.size() - 2].end;
        } else if ((pieces[i].end - chain.back().end).norm() <= gap) {
          chain.push_back(morph::planar::reversed(pieces[i]));
          chain.back().start = chain[chain.size() - 2].end;
        } else if ((pieces[i].end - chain.front().start).norm() <= gap) {
          chain.insert(chain.begin(), pieces[i]);
          chain.front().end = chain[1].start;
        } else if ((pieces[i].start - chain.front().start).norm() <= gap) {
          chain.insert(chain.begin(), morph::planar::reversed(pieces[i]));
          chain.front().end = chain[1].start;
        } else {
          continue;
        }
        used[i] = 1;
        grew = true;
      }
    }
    if (chain.size() > 1 && (chain.back().end - chain.front().start).norm() <= gap) {
      chain.back().end = chain.front().start;
      shapes.closed.push_back(Loop{chain});
    } else
      shapes.open.push_back(chain);
  }
}

}  // namespace

PlanarShapes read_dxf_shapes(const std::string& path) {
  const std::vector<Group> groups = read_groups(path);
  std::size_t i = 0;
  // Find the ENTITIES section.
  for (; i + 1 < groups.size(); ++i)
    if (groups[i].code == 0 && groups[i].value == "SECTION" && groups[i + 1].code == 2 &&
        groups[i + 1].value == "ENTITIES")
      break;
  if (i + 1 >= groups.size()) throw InputError(path + ": no ENTITIES section");
  i += 2;
  std::vector<Entity> entities;
  for (; i < groups.size(); ++i) {
    if (groups[i].code == 0) {
      if (groups[i].value == "ENDSEC") break;
      entities.push_back(Entity{groups[i].value, groups[i].line, {}});
    } else if (!entities.empty()) {
      entities.back().groups.push_back(groups[i]);
    }
  }
  PlanarShapes shapes;
  std::vector<Curve> open;
  morph::planar::Box2 extent;
  for (const Entity& e : entities) {
    Ocs ocs;
    ocs.mirrored = e.number(230, path, 1.0) < 0.0;
    if (e.type == "LINE") {
      const Vec2 a(e.number(10, path), e.number(20, path)), b(e.number(11, path), e.number(21, path));
      if (a == b) continue;  // a zero-length LINE bounds nothing
      open.push_back(morph::planar::make_segment(a, b, {{}, 0, e.line}));
    } else if (e.type == "ARC") {
      open.push_back(arc_entity(e, path, ocs));
    } else if (e.type == "CIRCLE") {
      const Vec2 c = ocs.point(e.number(10, path), e.number(20, path));
      const double r = e.number(40, path);
      if (!(r > 0.0)) throw InputError(fmt::format("{}:{}: CIRCLE with radius {}", path, e.line, r));
      Loop loop;
      loop.curves.push_back(morph::planar::make_arc(c, r, 0.0, M_PI, {{}, 0, e.line}));
      loop.curves.push_back(morph::planar::make_arc(c, r, M_PI, M_PI, {{}, 0, e.line}));
      loop.curves[1].start = loop.curves[0].end;
      loop.curves[1].end = loop.curves[0].start;
      shapes.closed.push_back(loop);
    } else if (e.type == "LWPOLYLINE") {
      const bool closed = (static_cast<int>(e.number(70, path, 0.0)) & 1) != 0;
      std::vector<Vec2> points;
      std::vector<double> bulges;
      double x = NAN;
      for (const Group& g : e.groups) {
        if (g.code == 10) x = Entity::parse(g, path);
        if (g.code == 20) {
          if (std::isnan(x)) throw InputError(fmt::format("{}:{}: LWPOLYLINE y without x", path, g.line));
          points.push_back(ocs.point(x, Entity::parse(g, path)));
          bulges.push_back(0.0);
          x = NAN;
        }
        if (g.code == 42 && !bulges.empty())
          bulges.back() = (ocs.mirrored ? -1.0 : 1.0) * Entity::parse(g, path);
      }
      if (points.size() < 2)
        throw InputError(fmt::format("{}:{}: LWPOLYLINE with fewer than two vertices", path, e.line));
      std::vector<Curve> curves;
      const std::size_t n = closed ? points.size() : points.size() - 1;
      for (std::size_t k = 0; k < n; ++k) {
        const Vec2& a = points[k];
        const Vec2& b = points[(k + 1) % points.size()];
        if (a == b) continue;
        curves.push_back(morph::planar::make_bulge(a, b, bulges[k], {{}, 0, e.line}));
      }
      if (closed)
        shapes.closed.push_back(Loop{curves});
      else
        open.insert(open.end(), curves.begin(), curves.end());
    } else {
      throw InputError(fmt::format(
          "{}:{}: DXF entity {} is not supported (LINE, ARC, CIRCLE, LWPOLYLINE are)", path, e.line, e.type));
    }
  }
  for (const Curve& c : open) extent.extend(morph::planar::bounds(c));
  // Ends closer than a millionth of the drawing (DXF writers print 6 decimals) are one point.
  const double gap = 1e-6 * std::max(1.0, extent.isEmpty() ? 1.0 : extent.sizes().maxCoeff());
  chain(std::move(open), gap, shapes);
  if (shapes.closed.empty() && shapes.open.empty())
    throw InputError(path + ": no LINE, ARC, CIRCLE or LWPOLYLINE");
  return shapes;
}

void write_region_dxf(const morph::planar::Region& region, const std::string& path) {
  AtomicOutput out(path);
  out << "0\nSECTION\n2\nENTITIES\n";
  for (const Loop& loop : region.loops)
    for (const Curve& c : loop.curves) {
      if (!c.is_arc()) {
        out << fmt::format("0\nLINE\n8\nRESULT\n10\n{:.12g}\n20\n{:.12g}\n11\n{:.12g}\n21\n{:.12g}\n",
                           c.start.x(), c.start.y(), c.end.x(), c.end.y());
        continue;
      }
      // DXF arcs run counter-clockwise from angle 50 to angle 51.
      const Curve ccw = c.sweep > 0.0 ? c : morph::planar::reversed(c);
      const double a0 =
          std::atan2(ccw.start.y() - ccw.center.y(), ccw.start.x() - ccw.center.x()) * 180.0 / M_PI;
      const double a1 = a0 + ccw.sweep * 180.0 / M_PI;
      out << fmt::format(
          "0\nARC\n8\nRESULT\n10\n{:.12g}\n20\n{:.12g}\n40\n{:.12g}\n50\n{:.12g}\n51\n{:.12g}\n",
          c.center.x(), c.center.y(), c.radius, a0, a1);
    }
  out << "0\nENDSEC\n0\nEOF\n";
  out.commit();
}

}  // namespace morphmill
