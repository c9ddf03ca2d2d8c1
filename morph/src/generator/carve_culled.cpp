// SPDX-License-Identifier: Apache-2.0
#include <morph/aabb_tree.h>
#include <morph/carve_culled.h>
#include <morph/exceptions.h>
#include <morph/joint_culling.h>
#include <morph/stock_face_cells.h>
#include <morph/tool_bounds.h>

#include "generator/own_facet.h"
#include "generator/sweep_plane_cache.h"
#include "generator/tool_facet_groups.h"

#include <tbb/enumerable_thread_specific.h>

#include <algorithm>
#include <ctime>
#include <map>
#include <memory>
#include <optional>
#include <tuple>
#include <unordered_map>

namespace morph {
namespace {

using Eigen::AlignedBox3d;
using Eigen::Vector3d;

double thread_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// The moves of one tool, culled together (the culling knows one tool polytope).
struct ToolGroup {
  const SweepPolytopeBuilder* builder = nullptr;
  std::vector<std::uint32_t> global;  ///< local move index -> index in the job's sweeps
  std::unique_ptr<SweepCulling> culling;
  std::unique_ptr<ToolFacetGroups> facet_groups;
  std::vector<std::vector<int>> facet_members;  ///< of each facet group
  ToolBounds bounds;                            ///< of the tool polytope (tool_bounds.h)
  ToolIncidence incidence;                      ///< what meets at each tool vertex (own_facet.h)
};

// From this many tool facets on, a stock piece's cutter whose planes the cache cannot hold makes
// the planes it needs one at a time (reaching_planes()).
constexpr std::size_t kPlanesMadeOneAtATime = 4096;

// One thread's memory of sweeps' planes made one at a time (SweepPolytopeBuilder::Planes, bit for
// bit sweep_planes()'): a move's kept facets ask for the same planes of their cutters, and the
// next moves (a raster's next pass) for the same cutters again. Making a cutter's Planes takes a
// side per tool facet, and each plane integer arithmetic: bear.nc at 0.01 spent 8% of its time
// remaking them.
class MadePlanes {
 public:
  /// Sweep j's planes one at a time (valid until the next call).
  const SweepPolytopeBuilder::Planes& sweep(std::uint32_t j, const CarveSweep& s) {
    return entry(j, s).planes;
  }
  /// Appends sweep j's planes at `indices`, ranked: sweep_planes()' planes at those indices.
  void append(std::uint32_t j, const CarveSweep& s, const PlaneIndices& indices,
              std::vector<ExactPlane>& out) {
    if (pool_.size() + indices.size() > kPlanesHeld) clear();
    Entry& e = entry(j, s);
    if (e.slot.empty()) e.slot.assign(e.planes.size(), kNone);
    for (int k : indices) {
      std::uint32_t& slot = e.slot[static_cast<std::size_t>(k)];
      if (slot == kNone) {
        slot = static_cast<std::uint32_t>(pool_.size());
        pool_.push_back(sweep_plane(e.planes[static_cast<std::size_t>(k)], j, static_cast<std::uint32_t>(k)));
      }
      out.push_back(pool_[slot]);
    }
  }

 private:
  static constexpr std::size_t kSweepsHeld = 4096;      ///< a few kB each
  static constexpr std::size_t kPlanesHeld = 1u << 18;  ///< ~25 MB
  static constexpr std::uint32_t kNone = ~std::uint32_t{0};
  struct Entry {
    SweepPolytopeBuilder::Planes planes;
    std::vector<std::uint32_t> slot;  ///< per plane index: its place in the pool, or kNone
  };
  Entry& entry(std::uint32_t j, const CarveSweep& s) {
    if (sweeps_.size() > kSweepsHeld) clear();
    auto found = sweeps_.find(j);
    if (found == sweeps_.end())
      found = sweeps_.emplace(j, Entry{SweepPolytopeBuilder::Planes(*s.tool, s.from, s.to), {}}).first;
    return found->second;
  }
  void clear() {
    sweeps_.clear();
    pool_.clear();
  }
  std::unordered_map<std::uint32_t, Entry> sweeps_;
  std::vector<ExactPlane> pool_;  ///< the planes made, each once
};

// Per thread: the culling's scratch per tool, the counts and the CPU seconds.
struct Worker {
  std::vector<SweepCulling::Scratch> scratch;
  OwnFacetScratch own_facet;
  std::vector<char> stock_marks;           ///< per tool facet, all clear between uses
  std::vector<ExactPlane> stock_reaching;  ///< a stock piece's cutter's planes that may reach it
  /// Sweeps' planes made one at a time: the kept facets' cutters', and the stock pieces' cutters'
  /// (all of a sweep's planes are ~1 MB at tolerance 1e-3, and a stock face meets every sweep,
  /// more than the plane cache holds).
  MadePlanes made;
  SweepPlaneCache planes;
  /// A kept facet's cutters' planes, one list per cutter, reused from facet to facet.
  std::vector<std::vector<ExactPlane>> cutter_planes;
  CarveStages stages;
};
using Workers = tbb::enumerable_thread_specific<Worker>;

// `pieces` minus each cutter in turn (as carve_box() does in the same order).
// A piece a cutter misses goes on whole with its look (RoughCorners), made once for all the
// cutters that miss it: a dense engraving's kept facet meets many. The parts a cutter leaves
// take their old corners from the piece's look; only those on its planes are looked at anew.
void minus_cutters(std::vector<ConvexPiece>& pieces,
                   const std::vector<const std::vector<ExactPlane>*>& cutters) {
  if (pieces.empty() || cutters.empty()) return;
  // The thread's lists (minus_cutters() does not nest), their storage kept from facet to facet.
  thread_local std::vector<ConvexPiece> next;
  thread_local std::vector<RoughCorners> looks, next_looks;
  looks.clear();
  for (const ConvexPiece& piece : pieces) looks.emplace_back(piece);
  for (const std::vector<ExactPlane>* cutter : cutters) {
    if (pieces.empty()) return;
    next.clear();
    next_looks.clear();
    for (std::size_t i = 0; i < pieces.size(); ++i)
      if (!subtract(pieces[i], looks[i], *cutter, next, &next_looks))
        next_looks.push_back(std::move(looks[i]));
    pieces.swap(next);
    looks.swap(next_looks);
  }
}

class Carving {
 public:
  Carving(const StockPolytope& stock, const std::vector<CarveSweep>& sweeps)
      : sweeps_(sweeps),
        stock_(stock),
        boxes_(sweep_boxes(sweeps)),
        tree_(boxes_),
        lattice_(CellLattice::of(stock.bounds, boxes_)) {
    std::map<const SweepPolytopeBuilder*, std::size_t> group_index;
    group_of_.resize(sweeps.size());
    local_of_.resize(sweeps.size());
    for (std::size_t g = 0; g < sweeps.size(); ++g) {
      auto [it, added] = group_index.emplace(sweeps[g].tool, groups_.size());
      if (added)
        groups_.push_back(ToolGroup{sweeps[g].tool,
                                    {},
                                    nullptr,
                                    std::make_unique<ToolFacetGroups>(sweeps[g].tool->tool()),
                                    {},
                                    {},
                                    {}});
      group_of_[g] = it->second;
      local_of_[g] = groups_[it->second].global.size();
      groups_[it->second].global.push_back(static_cast<std::uint32_t>(g));
    }
    for (std::size_t t = 0; t < groups_.size(); ++t) {
      ToolGroup& group = groups_[t];
      std::vector<Move> moves;
      std::vector<bool> joined;
      for (std::uint32_t g : group.global) {
        Move m;
        m.start = sweeps[g].from;
        m.end = sweeps[g].to;
        m.tool = static_cast<int>(t);
        // A joint only between moves next to each other in the job.
        joined.push_back(!moves.empty() && g > 0 && group_of_[g - 1] == t &&
                         joined_at_joint(*group.builder, moves.back(), m));
        moves.push_back(m);
      }
      for (std::size_t i = 0; i < group.facet_groups->size(); ++i)
        group.facet_members.push_back(group.facet_groups->members(i));
      group.bounds = tool_bounds(group.builder->tool());
      group.incidence = tool_incidence(*group.builder);
      largest_inner_radius_ = std::max(largest_inner_radius_, group.bounds.inner_radius);
      group.culling =
          std::make_unique<SweepCulling>(*group.builder, std::move(moves), std::move(joined), stock.bounds);
    }
    for (std::size_t g = 0; g < sweeps.size(); ++g)
      inner_boxes_.push_back(inner_box(groups_[group_of_[g]].bounds, sweeps[g].from, sweeps[g].to));
  }

  std::size_t tools() const { return groups_.size(); }
  std::size_t stock_faces() const { return stock_face_count(stock_); }

  // Stock face f in cells, each minus every sweep whose box meets it, in move order.
  std::vector<ConvexPiece> stock_face(int f, Workers& workers, ExecutionPolicy policy) const {
    ConvexPiece face = morph::stock_face(stock_, static_cast<std::size_t>(f));
    ++workers.local().stages.carve.facets;
    std::vector<std::uint32_t> near;
    tree_.for_each_overlapping(reach_of(face),
                               [&](std::size_t j) { near.push_back(static_cast<std::uint32_t>(j)); });
    std::sort(near.begin(), near.end());
    std::vector<ConvexPiece> out;
    if (face.empty()) return out;
    // Cells first (stock_face_cells.h), each minus the sweeps near it.
    std::vector<FaceCell> cells = stock_face_cells(face, near, boxes_, lattice_);
    std::vector<std::vector<ConvexPiece>> results(cells.size());
    for_each_index(policy, 0, cells.size(), [&](std::size_t i) {
      carve_stock_piece(std::move(cells[i].piece), 0, cells[i].sweeps, results[i], workers, policy);
    });
    for (std::vector<ConvexPiece>& r : results)
      for (ConvexPiece& p : r) out.push_back(std::move(p));
    sort_pieces(out);
    return out;
  }

  // `piece` minus the sweeps near[k...]. Each part of a split goes on by itself (the pieces are
  // the same whatever the order they are carved in): the largest in this loop, the others, which
  // lie along the cut, in parallel; their pieces come first, in part order.
  void carve_stock_piece(ConvexPiece piece, std::size_t k, const std::vector<std::uint32_t>& near,
                         std::vector<ConvexPiece>& out, Workers& workers, ExecutionPolicy policy) const {
    AlignedBox3d box = reach_of(piece);
    // A ball about the piece's exact corners, the same for every sweep until the piece is split.
    std::optional<Ball> ball = corner_ball(piece);
    if (hidden_later(ball, box, k, near)) return;
    // Its rounded corners, likewise: a sweep one of whose planes leaves them all outside misses
    // the piece (subtract() would find that out only after clipping by the planes before).
    std::optional<RoughCorners> look(piece);
    std::vector<ConvexPiece> parts;
    // CPU time is read when this thread starts or stops carving the piece, not for each cutter:
    // a thread's CPU clock is a system call, and a V-bit's engraving cells meet hundreds of sweeps.
    Worker& w = workers.local();
    double start = thread_seconds();
    for (; k < near.size(); ++k) {
      const std::uint32_t j = near[k];
      if (!box.intersects(boxes_[j])) continue;
      parts.clear();
      const std::vector<ExactPlane>& planes = reaching_planes(ball, j, near.size(), w);
      const bool missed =
          std::any_of(planes.begin(), planes.end(), [&](const ExactPlane& h) { return look->outside(h); });
      const bool reached = !missed && subtract(piece, *look, planes, parts);
      ++w.stages.carve.cutters;
      if (!reached) continue;
      if (parts.empty()) {
        w.stages.seconds_stock += thread_seconds() - start;
        return;
      }
      std::vector<AlignedBox3d> boxes;
      std::size_t largest = 0;
      for (std::size_t i = 0; i < parts.size(); ++i) {
        boxes.push_back(reach_of(parts[i]));
        if (boxes[i].diagonal().squaredNorm() > boxes[largest].diagonal().squaredNorm()) largest = i;
      }
      std::vector<std::vector<ConvexPiece>> results(parts.size());
      w.stages.seconds_stock += thread_seconds() - start;  // the parts below time themselves
      for_each_index(policy, 0, parts.size(), [&](std::size_t i) {
        if (i != largest) carve_stock_piece(std::move(parts[i]), k + 1, near, results[i], workers, policy);
      });
      start = thread_seconds();
      for (std::vector<ConvexPiece>& r : results)
        for (ConvexPiece& p : r) out.push_back(std::move(p));
      piece = std::move(parts[largest]);
      box = boxes[largest];
      ball = corner_ball(piece);
      if (hidden_later(ball, box, k + 1, near)) {
        w.stages.seconds_stock += thread_seconds() - start;
        return;
      }
      look.emplace(piece);
    }
    w.stages.seconds_stock += thread_seconds() - start;
    out.push_back(std::move(piece));
  }

  // The kept facets of sweep g, each minus its cutters: (facet, pieces) in facet order; each
  // facet's cutting order to `orders` when given.
  std::vector<std::pair<int, std::vector<ConvexPiece>>> sweep(
      std::uint32_t g, Worker& w, std::vector<std::pair<int, std::vector<std::uint32_t>>>* orders) const {
    double start = thread_seconds();
    const std::size_t t = group_of_[g];
    const ToolGroup& group = groups_[t];
    const std::vector<KeptFacet> kept = group.culling->cull(local_of_[g], w.stages.culling, w.scratch[t]);
    const double culled = thread_seconds();
    w.stages.seconds_cull += culled - start;
    std::vector<std::pair<int, std::vector<ConvexPiece>>> out;
    if (kept.empty()) return out;
    const CarveSweep& s = sweeps_[g];
    OwnPlanes own = own_planes(*group.builder, *group.facet_groups, group.facet_members, group.incidence,
                               s.from, s.to, g);
    // Every kept facet within the stock and its own sweep first, then each minus its cutters: the
    // two phases timed once per move (a thread's CPU clock is a system call).
    std::vector<ConvexPiece> facets;
    facets.reserve(kept.size());
    const PredicateCounts before = predicate_counts();
    for (const KeptFacet& k : kept)
      facets.push_back(
          own_facet(own, k.facet, facet_points(*group.builder, own, k.facet), stock_, w.own_facet));
    w.stages.carve.facets += static_cast<double>(kept.size());
    w.stages.seconds_own_facets += thread_seconds() - culled;
    w.stages.predicates_own += static_cast<double>(predicate_counts().calls - before.calls);
    w.stages.exact_own += static_cast<double>(predicate_counts().exact - before.exact);
    w.stages.ties += static_cast<double>(predicate_counts().ties - before.ties);
    w.stages.refined += static_cast<double>(predicate_counts().refined - before.refined);
    const PredicateCounts cut_before = predicate_counts();
    for (std::size_t f = 0; f < kept.size(); ++f) {
      const KeptFacet& k = kept[f];
      ConvexPiece& facet = facets[f];
      if (facet.empty()) continue;
      // The listed cutters with their crossing planes, and other tools' sweeps with all theirs,
      // in the worker's lists.
      struct Cutter {
        std::uint32_t move;
        std::size_t list;  // in the worker's lists (which may move as they grow)
        int points_below;
      };
      std::vector<std::vector<ExactPlane>>& lists = w.cutter_planes;
      std::size_t used = 0;
      auto next_list = [&]() -> std::vector<ExactPlane>& {
        if (used == lists.size()) lists.emplace_back();
        lists[used].clear();
        return lists[used++];
      };
      std::vector<Cutter> cutters;
      cutters.reserve(k.cutters.size());
      for (const FacetCutter& c : k.cutters) {
        // Made only where a cutter crosses a kept facet (sweep_planes()' planes at those indices).
        const std::uint32_t j = group.global[c.move];
        w.made.append(j, sweeps_[j], k.planes_of(c), next_list());
        cutters.push_back({j, used - 1, c.points_below});
      }
      if (groups_.size() > 1)
        tree_.for_each_overlapping(reach_of(facet), [&](std::size_t j) {
          if (group_of_[j] != t) {
            next_list() = planes_of(static_cast<std::uint32_t>(j), w);
            cutters.push_back({static_cast<std::uint32_t>(j), used - 1, 0});
          }
        });
      // Those that may hold the most of it first (carve_culled.h).
      std::sort(cutters.begin(), cutters.end(), [&](const Cutter& x, const Cutter& y) {
        if (x.points_below != y.points_below) return x.points_below > y.points_below;
        if (lists[x.list].size() != lists[y.list].size()) return lists[x.list].size() < lists[y.list].size();
        return x.move < y.move;
      });
      std::vector<const std::vector<ExactPlane>*> order;
      order.reserve(cutters.size());
      for (const Cutter& c : cutters) order.push_back(&lists[c.list]);
      if (orders) {
        orders->emplace_back(k.facet, std::vector<std::uint32_t>{});
        for (const Cutter& c : cutters) orders->back().second.push_back(c.move);
      }
      w.stages.carve.cutters += static_cast<double>(order.size());
      std::vector<ConvexPiece> pieces;
      pieces.push_back(std::move(facet));
      minus_cutters(pieces, order);
      if (stock_.mesh) pieces = keep_inside(*stock_.mesh, std::move(pieces));
      if (!pieces.empty()) out.emplace_back(k.facet, std::move(pieces));
    }
    w.stages.predicates_cut += static_cast<double>(predicate_counts().calls - cut_before.calls);
    w.stages.exact_cut += static_cast<double>(predicate_counts().exact - cut_before.exact);
    w.stages.ties += static_cast<double>(predicate_counts().ties - cut_before.ties);
    w.stages.refined += static_cast<double>(predicate_counts().refined - cut_before.refined);
    w.stages.seconds_facets += thread_seconds() - culled;
    return out;
  }

 private:
  // Sweep j's planes that may reach the exact corners of `piece`, in their order (valid until the
  // thread's next use). The others hold every corner strictly inside: with the piece only
  // shrinking as it is clipped, they would leave every clip of subtract() unchanged, so it gives
  // the same pieces without them. Found through the tool facets' groups (placed at either end,
  // then each plane tested by itself), as own_facet()'s second loop does.
  // `cutters`: how many sweeps the stock face meets. When the plane cache cannot hold them all,
  // asking it for each would rebuild every sweep's planes for every piece: then, for a tool of
  // many facets, the planes are made one at a time, only those the groups list. A tool of few
  // facets rebuilds all its sweep's planes for less than it makes the listed ones one at a time
  // (bear's first 1000 moves at 0.01, ~600 facets: stock faces 0.42 CPU s through the cache,
  // 0.80 one at a time; the target at 1e-3, 10,700 facets: 10.9 through it, 6.2 one at a time).
  const std::vector<ExactPlane>& reaching_planes(const std::optional<Ball>& corners, std::uint32_t j,
                                                 std::size_t cutters, Worker& w) const {
    if (!corners) return planes_of(j, w);
    const CarveSweep& s = sweeps_[j];
    const std::size_t tool_facets = s.tool->tool().facets.size();
    const bool cached = cutters <= w.planes.sweeps_held(tool_facets) || tool_facets < kPlanesMadeOneAtATime;
    const Ball& ball = *corners;
    const std::vector<Ball> balls{ball};
    const auto [a, b] = s.tool->degenerate(s.from, s.to) ? std::pair{s.from, s.from}
                                                         : SweepPolytopeBuilder::ordered(s.from, s.to);
    const ToolFacetGroups& facet_groups = *groups_[group_of_[j]].facet_groups;
    std::vector<char>& marks = w.stock_marks;
    marks.resize(tool_facets, 0);
    int lowest = static_cast<int>(tool_facets), highest = -1;
    facet_groups.for_each_reaching(ball.first, ball.second, a, b, 0.0, [&](int k) {
      marks[static_cast<std::size_t>(k)] = 1;
      lowest = std::min(lowest, k);
      highest = std::max(highest, k);
      return true;
    });
    const std::vector<ExactPlane>* all = cached ? &planes_of(j, w) : nullptr;
    const SweepPolytopeBuilder::Planes* planes = nullptr;
    if (!cached) planes = &w.made.sweep(j, s);
    std::vector<ExactPlane>& out = w.stock_reaching;
    out.clear();
    auto keep = [&](std::size_t k) {
      ExactPlane h;
      if (all) {
        h = (*all)[k];
      } else {  // sweep_planes()' plane k, bit for bit
        const Halfspace x = (*planes)[k];
        h = sweep_plane(x, j, static_cast<std::uint32_t>(k));
      }
      if (!below_in_balls(h, h.normal.norm(), balls, 1e-9 * (1 + std::fabs(h.offset)))) out.push_back(h);
    };
    for (int k = lowest; k <= highest; ++k)
      if (marks[static_cast<std::size_t>(k)]) {
        marks[static_cast<std::size_t>(k)] = 0;
        keep(static_cast<std::size_t>(k));
      }
    for (std::size_t k = tool_facets, n = all ? all->size() : planes->size(); k < n; ++k) keep(k);
    return out;
  }

  // Sweep j's planes, from this thread's cache (valid until its next use).
  const std::vector<ExactPlane>& planes_of(std::uint32_t j, Worker& w) const {
    return w.planes.get(
        j, [&] { return sweep_planes(sweeps_[j].tool->halfspaces(sweeps_[j].from, sweeps_[j].to), j); });
  }

  // True when one of the sweeps near[k...] whose box meets `box` holds the ball strictly inside
  // (tool_bounds.h): the piece whose exact corners the ball holds lies inside that sweep, so
  // every part the sweeps before it would cut it into lies inside it too, and carving the piece
  // on would leave nothing. Most cells of a machined face lie deep in one later pass.
  bool hidden_later(const std::optional<Ball>& ball, const AlignedBox3d& box, std::size_t k,
                    const std::vector<std::uint32_t>& near) const {
    if (!ball || !(ball->second < largest_inner_radius_)) return false;
    const AlignedBox3d ball_box(ball->first.array() - ball->second, ball->first.array() + ball->second);
    for (; k < near.size(); ++k) {
      const std::uint32_t j = near[k];
      // A V-bit's engraving cells meet hundreds of sweeps' boxes but lie in few inner regions.
      if (!box.intersects(boxes_[j]) || !inner_boxes_[j].contains(ball_box)) continue;
      const CarveSweep& s = sweeps_[j];
      if (ball_inside_sweep(groups_[group_of_[j]].bounds, s.from, s.to, ball->first, ball->second))
        return true;
    }
    return false;
  }

  const std::vector<CarveSweep>& sweeps_;
  const StockPolytope& stock_;
  std::vector<AlignedBox3d> boxes_;
  std::vector<AlignedBox3d> inner_boxes_;  ///< of each sweep's inner bounds (inner_box())
  AabbTree tree_;
  CellLattice lattice_;
  std::vector<ToolGroup> groups_;
  std::vector<std::size_t> group_of_, local_of_;
  double largest_inner_radius_ = 0.0;
};

}  // namespace

std::vector<AlignedBox3d> sweep_boxes(const std::vector<CarveSweep>& sweeps) {
  std::vector<AlignedBox3d> boxes;
  boxes.reserve(sweeps.size());
  // The tool's box once per run of sweeps of one tool (a tool has hundreds of vertices).
  const SweepPolytopeBuilder* last = nullptr;
  AlignedBox3d tool;
  for (const CarveSweep& s : sweeps) {
    if (s.tool != last) last = s.tool, tool = s.tool->tool().bounds();
    AlignedBox3d box = tool.translated(s.from);
    box.extend(tool.translated(s.to));
    boxes.push_back(grown_for_rounding(box));
  }
  return boxes;
}

CarvedPieces carve_culled(const AlignedBox3d& box, const std::vector<CarveSweep>& sweeps,
                          ExecutionPolicy policy, CarveStages* stages, Progress* progress,
                          CuttingOrders* orders) {
  return carve_culled(box_stock_polytope(box), sweeps, policy, stages, progress, orders);
}

CarvedPieces carve_culled(const StockPolytope& stock, const std::vector<CarveSweep>& sweeps,
                          ExecutionPolicy policy, CarveStages* stages, Progress* progress,
                          CuttingOrders* orders) {
  Progress& report = progress ? *progress : null_progress();
  const double start = thread_seconds();
  const Carving carving(stock, sweeps);
  const double setup = thread_seconds() - start;
  Workers workers([&] {
    Worker w;
    w.scratch.resize(carving.tools());
    return w;
  });
  // Items 0 to faces-1: the stock faces; then one per move. Each writes its own slot.
  const std::size_t faces = carving.stock_faces();
  // Each slot's pieces with their planes in its own table as soon as it is carved: the slots
  // together were the largest memory of the run (carved_pieces.h).
  std::vector<CarvedPieces> slots(faces + sweeps.size());
  std::vector<std::vector<std::pair<int, std::vector<std::uint32_t>>>> order_slots(orders ? sweeps.size()
                                                                                          : 0);
  report.begin("erode: carve", slots.size());
  for_each_index(policy, 0, slots.size(), [&](std::size_t item) {
    if (report.interrupted()) return;
    Worker& w = workers.local();
    std::vector<CarvedPiece> out;
    if (item < faces) {
      for (ConvexPiece& p : carving.stock_face(static_cast<int>(item), workers, policy))
        out.push_back(CarvedPiece{canonical(std::move(p)), -1, static_cast<std::int32_t>(item)});
    } else {
      const auto g = static_cast<std::uint32_t>(item - faces);
      for (auto& [facet, pieces] : carving.sweep(g, w, orders ? &order_slots[g] : nullptr))
        for (ConvexPiece& p : pieces)
          out.push_back(CarvedPiece{canonical(std::move(p)), static_cast<std::int32_t>(g), facet});
    }
    slots[item] = compact(out);
    report.advance(1);
  });
  report.end();
  if (report.interrupted()) throw Interrupted("erode: carve interrupted");
  if (orders)
    for (std::size_t g = 0; g < order_slots.size(); ++g)
      for (auto& [facet, order] : order_slots[g])
        (*orders)[{static_cast<std::int32_t>(g), facet}] = std::move(order);
  CarveStages total;
  total.seconds_setup = setup;
  for (const Worker& w : workers) {
    total.culling += w.stages.culling;
    total.carve.facets += w.stages.carve.facets;
    total.carve.cutters += w.stages.carve.cutters;
    total.seconds_cull += w.stages.seconds_cull;
    total.seconds_facets += w.stages.seconds_facets;
    total.seconds_stock += w.stages.seconds_stock;
    total.seconds_own_facets += w.stages.seconds_own_facets;
    total.predicates_own += w.stages.predicates_own;
    total.exact_own += w.stages.exact_own;
    total.predicates_cut += w.stages.predicates_cut;
    total.exact_cut += w.stages.exact_cut;
    total.ties += w.stages.ties;
    total.refined += w.stages.refined;
  }
  CarvedPieces out = concatenated(slots, policy);
  total.carve.pieces = static_cast<double>(out.size());
  if (stages) *stages = total;
  return out;
}

}  // namespace morph
