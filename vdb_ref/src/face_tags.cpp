// SPDX-License-Identifier: Apache-2.0
#include "face_tags.h"

#include <morph/aabb_tree.h>
#include <morph/exceptions.h>
#include <morph/mesh_distance.h>
#include <morph/stock.h>
#include <morph/sweep_distance.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

#include "straight_sweep.h"

namespace vdb_ref::detail {

namespace {

// Distances this close (job units) count as a tie between moves.
constexpr double kTie = 1e-9;

// The exact sweep distance of every move of a job, with a hierarchy of their swept bounds.
class MoveSweeps {
 public:
  explicit MoveSweeps(const morph::Job& job) : moves_(job.moves()) {
    std::vector<Eigen::AlignedBox3d> boxes;
    boxes.reserve(moves_.size());
    straight_.reserve(moves_.size());
    for (const morph::Move* move : moves_) {
      const morph::Tool& tool = job.tool_of(*move);
      tools_.push_back(&tool);
      boxes.push_back(morph::swept_bounds(tool, *move));
      if (move->is_arc())
        straight_.emplace_back();
      else
        straight_.emplace_back(StraightSweep(tool, move->start, move->end));
    }
    tree_ = morph::AabbTree(std::move(boxes));
  }

  // (move, distance) of the nearest sweep among those whose swept bounds come within `reach` of
  // p, which includes every sweep whose distance from p is <= reach; move -1 if there is none.
  std::pair<int, double> nearest_within(const Eigen::Vector3d& p, double reach) const {
    // The slack keeps a sweep at exactly `reach` (rounded) in the candidates.
    const Eigen::Vector3d grow = Eigen::Vector3d::Constant(reach + 1e-9 * (1.0 + reach + p.norm()));
    std::vector<std::pair<int, double>> candidates;
    double smallest = std::numeric_limits<double>::infinity();
    tree_.for_each_overlapping(Eigen::AlignedBox3d(p - grow, p + grow), [&](std::size_t i) {
      candidates.emplace_back(static_cast<int>(i), distance(i, p));
      smallest = std::min(smallest, candidates.back().second);
    });
    // Consecutive moves tie where they meet (up to the rounding of their distances): the earliest
    // move within kTie of the smallest distance wins, whatever order the candidates came in.
    std::pair<int, double> best{-1, smallest};
    for (const auto& [move, d] : candidates)
      if (d <= smallest + kTie && (best.first < 0 || move < best.first)) best.first = move;
    return best;
  }

  int line(int move) const { return moves_[static_cast<std::size_t>(move)]->line; }

 private:
  double distance(std::size_t i, const Eigen::Vector3d& p) const {
    if (straight_[i]) return straight_[i]->distance(p);
    return morph::swept_signed_distance(*tools_[i], *moves_[i], p);
  }

  std::vector<const morph::Move*> moves_;
  std::vector<const morph::Tool*> tools_;
  std::vector<std::optional<StraightSweep>> straight_;
  morph::AabbTree tree_;
};

}  // namespace

void tag_faces(const morph::Job& job, double search_radius, morph::TriangleMesh& mesh,
               morph::Progress& progress) {
  const MoveSweeps sweeps(job);
  std::optional<morph::MeshDistance> stock_mesh;
  if (job.stock.type == morph::StockType::Mesh) stock_mesh.emplace(job.stock.mesh);
  auto stock_distance = [&](const Eigen::Vector3d& p) {
    return stock_mesh ? stock_mesh->signed_distance(p) : morph::analytic_signed_distance(job.stock, p);
  };
  mesh.tags.assign(mesh.triangles.size(), morph::FaceTag{morph::PatchKind::Reference, -1, 0});
  std::atomic<bool> stop{false};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, mesh.triangles.size(), 256),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      if (stop || progress.interrupted()) {
                        stop = true;
                        return;
                      }
                      for (std::size_t t = range.begin(); t < range.end(); ++t) {
                        const morph::Triangle& tri = mesh.triangles[t];
                        const Eigen::Vector3d centroid =
                            (mesh.vertices[tri[0]] + mesh.vertices[tri[1]] + mesh.vertices[tri[2]]) / 3.0;
                        // Only a sweep within |stock| of the centroid can tag it; the nearest
                        // sweep within the search radius is the nearest of all if it is within
                        // that radius.
                        const double stock = std::abs(stock_distance(centroid));
                        const double reach = std::min(stock, search_radius);
                        auto [move, sweep] = sweeps.nearest_within(centroid, reach);
                        if (!(sweep <= reach) && stock > reach)
                          std::tie(move, sweep) = sweeps.nearest_within(centroid, stock);
                        if (move >= 0 && std::abs(sweep) <= stock) {
                          mesh.tags[t].source = move;
                          mesh.tags[t].line = sweeps.line(move);
                        }
                      }
                      progress.advance(range.size());
                    });
  if (progress.interrupted()) throw morph::Interrupted("reference: interrupted during mesh");
}

}  // namespace vdb_ref::detail
