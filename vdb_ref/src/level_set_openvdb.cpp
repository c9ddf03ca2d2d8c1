// SPDX-License-Identifier: Apache-2.0
// The only translation unit of MorphMill that includes OpenVDB (its headers cost ~50 s and ~2 GB
// to compile); everything else talks to it through level_set.h.
#include <morph/exceptions.h>
#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/Composite.h>
#include <openvdb/tools/LevelSetMeasure.h>
#include <openvdb/tools/LevelSetRebuild.h>
#include <openvdb/tools/LevelSetUtil.h>
#include <openvdb/tools/MeshToVolume.h>
#include <openvdb/tools/Prune.h>
#include <openvdb/tools/SignedFloodFill.h>
#include <openvdb/tools/ValueTransformer.h>
#include <openvdb/tools/VolumeToMesh.h>

#include <algorithm>
#include <cmath>
#include <mutex>

#include "level_set.h"

namespace vdb_ref::detail {

namespace {

using openvdb::FloatGrid;
using openvdb::FloatTree;

// OpenVDB's interrupter protocol on top of morph::Progress. OpenVDB stops early and returns a
// partial result when interrupted; check_interrupted() then turns that into an exception.
struct ProgressInterrupter {
  morph::Progress* progress = nullptr;
  void start(const char* = nullptr) {}
  void end() {}
  bool wasInterrupted(int = -1) { return progress != nullptr && progress->interrupted(); }
};

void check_interrupted(morph::Progress* progress, const char* stage) {
  if (progress != nullptr && progress->interrupted())
    throw morph::Interrupted(std::string("reference: interrupted during ") + stage);
}

void initialize_openvdb() {
  static std::once_flag once;
  std::call_once(once, [] { openvdb::initialize(); });
}

}  // namespace

struct LevelSetPipeline::Impl {
  double voxel_size = 0.0;
  float half_width = 3.0f;
  float background = 0.0f;
  morph::Progress* progress = nullptr;
  openvdb::math::Transform::Ptr transform;
  FloatGrid::Ptr stock;
  FloatGrid::Ptr sweep;
  FloatGrid::Ptr erosion;
  mutable std::size_t peak_bytes = 0;  // largest transient use inside one call (rebuild, meshing)

  void note(std::size_t bytes) const { peak_bytes = std::max(peak_bytes, bytes); }

  FloatGrid::Ptr make_grid(const SparseLevelSet& field) const {
    FloatGrid::Ptr grid = FloatGrid::create(background);
    grid->setTransform(transform->copy());
    grid->setGridClass(openvdb::GRID_LEVEL_SET);
    FloatTree& tree = grid->tree();
    for (std::size_t i = 0; i < field.leaf_origins.size(); ++i) {
      const auto& o = field.leaf_origins[i];
      auto* leaf = new FloatTree::LeafNodeType(openvdb::Coord(o[0], o[1], o[2]), background, false);
      const auto& values = field.leaf_values[i];
      for (int n = 0; n < kLeafVoxels; ++n) {
        const float v = values[n];
        if (std::abs(v) < background) {
          leaf->setValueOn(n, v);
        } else {
          leaf->setValueOff(n, v < 0.0f ? -background : background);
        }
      }
      tree.addLeaf(leaf);
    }
    // Interior blocks last: a block deeper than the band inside one sweep overrides whatever
    // another sweep's leaves said there (the union is the minimum).
    for (std::size_t i = 0; i < field.interior_origins.size(); ++i) {
      const auto& o = field.interior_origins[i];
      tree.fill(openvdb::CoordBBox::createCube(openvdb::Coord(o[0], o[1], o[2]), field.interior_sizes[i]),
                -background, false);
    }
    openvdb::tools::pruneLevelSet(tree);
    return grid;
  }

  // A clean signed distance to the zero iso-surface of `csg`, like tools::levelSetRebuild
  // (volume to mesh, then exact distance to that mesh), but with the sign taken from `csg` itself:
  // levelSetRebuild signs by flooding the outside from the grid's bounds, which fills internal
  // voids (a tool moving inside the stock) as solid.
  FloatGrid::Ptr rebuild(const FloatGrid& csg, ProgressInterrupter& interrupter) const {
    std::vector<openvdb::Vec3s> points;
    std::vector<openvdb::Vec3I> triangles;
    std::vector<openvdb::Vec4I> quads;
    openvdb::tools::volumeToMesh(csg, points, triangles, quads, 0.0, 0.0, true);
    check_interrupted(progress, "difference");
    note(csg.memUsage() + points.capacity() * sizeof(points[0]) + quads.capacity() * sizeof(quads[0]) +
         triangles.capacity() * sizeof(triangles[0]));
    // volumeToMesh gives world positions; the mesh adapter wants index space.
    for (openvdb::Vec3s& p : points) p = openvdb::Vec3s(transform->worldToIndex(openvdb::Vec3d(p)));
    // One polygon list: OpenVDB's mesh adapter reads a quad whose last index is INVALID_IDX as a
    // triangle.
    for (const openvdb::Vec3I& t : triangles)
      quads.emplace_back(t[0], t[1], t[2], openvdb::util::INVALID_IDX);
    triangles.clear();
    openvdb::tools::QuadAndTriangleDataAdapter<openvdb::Vec3s, openvdb::Vec4I> polygons(points, quads);
    FloatGrid::Ptr distance = openvdb::tools::meshToVolume<FloatGrid>(
        interrupter, polygons, *transform, half_width, half_width, openvdb::tools::UNSIGNED_DISTANCE_FIELD);
    check_interrupted(progress, "difference");
    note(csg.memUsage() + distance->memUsage() + points.capacity() * sizeof(points[0]) +
         quads.capacity() * sizeof(quads[0]));
    // Signs from the CSG result (exact at voxel centres, where the iso-surface was extracted),
    // then the inactive regions get their sign from their active neighbours.
    openvdb::tools::foreach (
        distance->beginValueOn(),
        [&csg](const FloatGrid::ValueOnIter& it) {
          if (csg.tree().getValue(it.getCoord()) < 0.0f) it.setValue(-*it);
        },
        true);
    FloatTree& tree = distance->tree();
    openvdb::tools::signedFloodFill(tree);
    openvdb::tools::pruneLevelSet(tree);
    distance->setGridClass(openvdb::GRID_LEVEL_SET);
    return distance;
  }
};

LevelSetPipeline::LevelSetPipeline(double voxel_size, double half_width_voxels, morph::Progress* progress)
    : impl_(std::make_unique<Impl>()) {
  initialize_openvdb();
  impl_->voxel_size = voxel_size;
  impl_->half_width = static_cast<float>(half_width_voxels);
  impl_->background = static_cast<float>(half_width_voxels * voxel_size);
  impl_->progress = progress;
  impl_->transform = openvdb::math::Transform::createLinearTransform(voxel_size);
}

LevelSetPipeline::~LevelSetPipeline() = default;

float LevelSetPipeline::background() const {
  return impl_->background;
}

void LevelSetPipeline::set_stock(const SparseLevelSet& stock) {
  impl_->stock = impl_->make_grid(stock);
}

void LevelSetPipeline::set_stock_mesh(const morph::TriangleMesh& mesh) {
  std::vector<openvdb::Vec3s> points;
  points.reserve(mesh.vertices.size());
  const openvdb::math::Transform& xform = *impl_->transform;
  for (const Eigen::Vector3d& v : mesh.vertices) {
    points.emplace_back(static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z()));
  }
  std::vector<openvdb::Vec3I> triangles;
  triangles.reserve(mesh.triangles.size());
  for (const morph::Triangle& t : mesh.triangles) triangles.emplace_back(t[0], t[1], t[2]);
  ProgressInterrupter interrupter{impl_->progress};
  impl_->stock =
      openvdb::tools::meshToLevelSet<FloatGrid>(interrupter, xform, points, triangles, impl_->half_width);
  check_interrupted(impl_->progress, "stock");
  impl_->stock->setGridClass(openvdb::GRID_LEVEL_SET);
}

void LevelSetPipeline::set_sweep(const SparseLevelSet& sweep) {
  impl_->sweep = impl_->make_grid(sweep);
}

void LevelSetPipeline::difference() {
  if (!impl_->stock || !impl_->sweep) throw std::logic_error("LevelSetPipeline: stock and sweep first");
  openvdb::tools::csgDifference(*impl_->stock, *impl_->sweep);
  impl_->sweep.reset();
  check_interrupted(impl_->progress, "difference");
  ProgressInterrupter interrupter{impl_->progress};
  if (impl_->stock->activeVoxelCount() == 0) {
    impl_->erosion = impl_->stock;  // nothing left (or nothing near a surface): keep the empty grid
  } else {
    impl_->erosion = impl_->rebuild(*impl_->stock, interrupter);
  }
  impl_->stock.reset();
  check_interrupted(impl_->progress, "difference");
  impl_->erosion->setGridClass(openvdb::GRID_LEVEL_SET);
  impl_->erosion->setName("erosion");
}

morph::TriangleMesh LevelSetPipeline::mesh() const {
  morph::TriangleMesh out;
  if (!impl_->erosion || impl_->erosion->activeVoxelCount() == 0) return out;
  std::vector<openvdb::Vec3s> points;
  std::vector<openvdb::Vec3I> triangles;
  std::vector<openvdb::Vec4I> quads;
  openvdb::tools::volumeToMesh(*impl_->erosion, points, triangles, quads, 0.0, 0.0, true);
  impl_->note(impl_->erosion->memUsage() + points.capacity() * sizeof(points[0]) +
              triangles.capacity() * sizeof(triangles[0]) + quads.capacity() * sizeof(quads[0]) +
              points.size() * sizeof(Eigen::Vector3d) +
              (triangles.size() + 2 * quads.size()) * sizeof(morph::Triangle));
  out.vertices.reserve(points.size());
  for (const openvdb::Vec3s& p : points) out.vertices.emplace_back(p.x(), p.y(), p.z());
  out.triangles.reserve(triangles.size() + 2 * quads.size());
  // volumeToMesh winds its polygons inward: reverse them. Quads are split along a fixed diagonal.
  for (const openvdb::Vec3I& t : triangles) out.triangles.push_back({t[0], t[2], t[1]});
  for (const openvdb::Vec4I& q : quads) {
    out.triangles.push_back({q[0], q[2], q[1]});
    out.triangles.push_back({q[0], q[3], q[2]});
  }
  return out;
}

std::vector<Segment> LevelSetPipeline::segments() const {
  std::vector<Segment> out;
  if (!impl_->erosion || impl_->erosion->activeVoxelCount() == 0) return out;
  std::vector<FloatGrid::Ptr> grids;
  openvdb::tools::segmentSDF(*impl_->erosion, grids);
  check_interrupted(impl_->progress, "segment");
  ProgressInterrupter interrupter{impl_->progress};
  for (FloatGrid::Ptr& grid : grids) {
    if (grid->activeVoxelCount() == 0) continue;
    grid->setGridClass(openvdb::GRID_LEVEL_SET);
    grid->setTransform(impl_->transform->copy());
    openvdb::tools::LevelSetMeasure<FloatGrid, ProgressInterrupter> measure(*grid, &interrupter);
    Segment segment;
    segment.area = measure.area(true);
    segment.volume = measure.volume(true);
    check_interrupted(impl_->progress, "segment");
    openvdb::CoordBBox inside;
    for (auto it = grid->tree().cbeginValueOn(); it; ++it) {
      if (*it > 0.0f) continue;
      inside.expand(it.getBoundingBox());
    }
    if (!inside.empty()) {
      const double h = impl_->voxel_size;
      segment.bounds =
          Eigen::AlignedBox3d(Eigen::Vector3d(inside.min().x(), inside.min().y(), inside.min().z()) * h,
                              Eigen::Vector3d(inside.max().x(), inside.max().y(), inside.max().z()) * h);
    }
    out.push_back(segment);
  }
  // A void's wall measures a negative volume; the solid around it is the smallest solid whose
  // flood-filled level set is negative (inside) on the void's wall.
  for (std::size_t i = 0; i < out.size(); ++i) {
    if (out[i].volume >= 0.0) continue;
    openvdb::Coord probe;
    bool found = false;
    const FloatGrid& wall = *grids[i];
    for (auto it = wall.tree().cbeginValueOn(); it && !found; ++it) {
      if (*it < 0.0f) {
        probe = it.getCoord();
        found = true;
      }
    }
    double smallest = std::numeric_limits<double>::infinity();
    for (std::size_t j = 0; j < out.size() && found; ++j) {
      if (j == i || out[j].volume <= 0.0) continue;
      if (grids[j]->tree().getValue(probe) < 0.0f && out[j].volume < smallest) {
        smallest = out[j].volume;
        out[i].enclosing = static_cast<int>(j);
      }
    }
  }
  return out;
}

void LevelSetPipeline::write(const std::string& path,
                             const std::vector<std::pair<std::string, std::string>>& metadata) const {
  if (!impl_->erosion) throw std::logic_error("LevelSetPipeline: no erosion to write");
  try {
    openvdb::io::File file(path);
    // A copy sharing the tree: the metadata belongs to the file, not to the pipeline's grid.
    openvdb::FloatGrid::Ptr grid = impl_->erosion->copy();
    for (const auto& [name, value] : metadata) grid->insertMeta(name, openvdb::StringMetadata(value));
    openvdb::GridPtrVec grids{grid};
    file.write(grids);
    file.close();
  } catch (const openvdb::Exception& e) {
    throw morph::IoError(path + ": cannot write the OpenVDB file: " + e.what());
  }
}

std::size_t LevelSetPipeline::active_voxels() const {
  return impl_->erosion ? static_cast<std::size_t>(impl_->erosion->activeVoxelCount()) : 0;
}

std::size_t LevelSetPipeline::memory_bytes() const {
  std::size_t bytes = 0;
  for (const FloatGrid::Ptr& grid : {impl_->stock, impl_->sweep, impl_->erosion})
    if (grid && grid != impl_->stock) bytes += grid->memUsage();
  if (impl_->stock) bytes += impl_->stock->memUsage();
  return std::max(bytes, impl_->peak_bytes);
}

}  // namespace vdb_ref::detail

namespace vdb_ref {

std::vector<GridMetadata> read_grid_metadata(const std::string& path) {
  openvdb::initialize();
  std::vector<GridMetadata> grids;
  try {
    openvdb::io::File file(path);
    file.open();
    const openvdb::GridPtrVecPtr all = file.readAllGridMetadata();  // kept alive for the loop
    for (const openvdb::GridBase::Ptr& grid : *all) {
      GridMetadata g{grid->getName(), {}};
      for (auto it = grid->beginMeta(); it != grid->endMeta(); ++it)
        if (it->second && it->second->typeName() == openvdb::StringMetadata::staticTypeName())
          g.entries.push_back({it->first, it->second->str()});
      grids.push_back(std::move(g));
    }
    file.close();
  } catch (const openvdb::Exception& e) {
    throw morph::IoError(path + ": cannot read the OpenVDB file: " + e.what());
  }
  return grids;
}

}  // namespace vdb_ref
