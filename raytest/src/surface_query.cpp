// SPDX-License-Identifier: Apache-2.0
#include <embree3/rtcore.h>
#include <morph/exceptions.h>
#include <morph/mesh_distance.h>
#include <morph/parallel.h>
#include <raytest/sampling.h>
#include <raytest/surface_query.h>
#include <tbb/parallel_sort.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <mutex>
#include <string>

namespace raytest {

namespace {

// Embree reports errors through a callback on its own (C) stack: record the first one and
// throw from our side after each call that can fail.
struct EmbreeErrors {
  std::mutex mutex;
  std::string first;
};

void record_embree_error(void* user, RTCError code, const char* message) {
  auto* errors = static_cast<EmbreeErrors*>(user);
  std::lock_guard<std::mutex> lock(errors->mutex);
  if (errors->first.empty())
    errors->first =
        "Embree error " + std::to_string(static_cast<int>(code)) + ": " + (message ? message : "");
}

constexpr std::uint32_t kNoHint = 0xffffffffu;

float round_up_to_float(double x) {
  if (!std::isfinite(x)) return std::numeric_limits<float>::infinity();
  const float f = static_cast<float>(x);
  return static_cast<double>(f) >= x ? f : std::nextafter(f, std::numeric_limits<float>::infinity());
}

// A triangle as the closest-point search reads it, in one place (no index to follow): its corners
// and planes that bound its distance from below much more cheaply than the exact closest point.
// The triangle lies in the slab |n.x - offset| <= half_width (n its unit normal; half_width is 0 up
// to rounding, and larger only when rounding makes the normal of a near-degenerate triangle
// meaningless) and inside the three half-spaces e.x <= offset of its edges (e the outward normal
// in the plane). A point outside the slab by s and outside an edge's half-space by t is then at
// least sqrt(s^2 + t^2) away; equality holds unless a corner is nearest. Offsets are taken from
// the corners themselves and rounded outwards, so the triangle is inside whatever the rounding;
// storing floats costs a few float epsilons of the coordinates, which the search's rounding
// margin covers.
struct TriangleRecord {
  std::array<float, 18> planes;  // n, offset, half_width, then (e, offset) of edges ab, bc, ca, 0
  Eigen::Vector3d a, b, c;

  static TriangleRecord of(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
    TriangleRecord record{{}, a, b, c};  // all zero: a bound of 0, every query measures the triangle
    const Eigen::Vector3d cross = (b - a).cross(c - a);
    const double length = cross.norm();
    if (!(length > 0) || !std::isfinite(length)) return record;
    const Eigen::Vector3d* corners[3] = {&a, &b, &c};
    const auto rounded = [](const Eigen::Vector3d& v) {
      return Eigen::Vector3d(double(float(v.x())), double(float(v.y())), double(float(v.z())));
    };
    const Eigen::Vector3d n = rounded(cross / length);
    double low = std::numeric_limits<double>::infinity(), high = -low;
    for (const Eigen::Vector3d* v : corners) {
      low = std::min(low, n.dot(*v));
      high = std::max(high, n.dot(*v));
    }
    const float offset = static_cast<float>(0.5 * (low + high));
    for (int k = 0; k < 3; ++k) record.planes[k] = static_cast<float>(n[k]);
    record.planes[3] = offset;
    record.planes[4] = round_up_to_float(std::max(high - double(offset), double(offset) - low));
    for (int e = 0; e < 3; ++e) {
      const Eigen::Vector3d edge = rounded((*corners[(e + 1) % 3] - *corners[e]).cross(n).normalized());
      if (!edge.allFinite()) return TriangleRecord{{}, a, b, c};
      double reach = -std::numeric_limits<double>::infinity();
      for (const Eigen::Vector3d* v : corners) reach = std::max(reach, edge.dot(*v));
      for (int k = 0; k < 3; ++k) record.planes[5 + 4 * e + k] = static_cast<float>(edge[k]);
      record.planes[5 + 4 * e + 3] = round_up_to_float(reach);
    }
    return record;
  }

  // Squared lower bound of the distance from p to the triangle, up to the float rounding above.
  double squared_distance_bound(const Eigen::Vector3d& p) const {
    const auto along = [&](int first) {
      const float* q = &planes[first];
      return double(q[0]) * p.x() + double(q[1]) * p.y() + double(q[2]) * p.z() - double(q[3]);
    };
    const double off_plane = std::max(0.0, std::abs(along(0)) - double(planes[4]));
    const double outside = std::max({0.0, along(5), along(9), along(13)});
    return off_plane * off_plane + outside * outside;
  }
};

}  // namespace

struct SurfaceQuery::Impl {
  morph::TriangleMesh mesh;
  EmbreeErrors errors;
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  double coordinate_scale = 0;  // max |coordinate| of the mesh: bounds float rounding errors
  // What the closest-point search reads of each triangle, in one place (no index to follow).
  std::vector<TriangleRecord> records;

  // Pseudo-normals for the sign, built on first use.
  mutable std::once_flag normals_once;
  mutable std::vector<Eigen::Vector3d> face_normals;
  mutable std::vector<Eigen::Vector3d> vertex_normals;
  mutable std::vector<std::array<Eigen::Vector3d, 3>> edge_normals;  // edge (k, k+1) of each triangle

  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }

  void check(const char* what) {
    std::lock_guard<std::mutex> lock(errors.mutex);
    if (!errors.first.empty())
      throw morph::GeometryError(std::string("SurfaceQuery: ") + what + ": " + errors.first);
  }

  // Distance slack covering the float rounding of the vertices, the query point and Embree's
  // bounds: triangles whose exact distance is below the best found so far are never pruned.
  double margin(const Eigen::Vector3d& p) const {
    return 16.0 * FLT_EPSILON * (coordinate_scale + p.cwiseAbs().maxCoeff()) + 1e-300;
  }

  void build_normals() const {
    // Built while every measuring thread waits for the sign of its first point: in parallel.
    const std::size_t nt = mesh.triangles.size();
    face_normals.resize(nt);
    morph::for_each_index(morph::ExecutionPolicy::Parallel, 0, nt,
                          [&](std::size_t t) { face_normals[t] = morph::face_normal(mesh, t); });
    vertex_normals = angle_weighted_vertex_normals(mesh);
    struct HalfEdge {
      std::uint64_t key;
      std::uint32_t slot;  // 3 * triangle + k
    };
    std::vector<HalfEdge> half_edges(3 * nt);
    morph::for_each_index(morph::ExecutionPolicy::Parallel, 0, nt, [&](std::size_t t) {
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t a = mesh.triangles[t][k], b = mesh.triangles[t][(k + 1) % 3];
        half_edges[3 * t + k] = {(std::uint64_t{std::min(a, b)} << 32) | std::max(a, b),
                                 static_cast<std::uint32_t>(3 * t + k)};
      }
    });
    // (key, slot) orders all half-edges totally: the same sequence, so the same sums, whatever the threads.
    tbb::parallel_sort(half_edges.begin(), half_edges.end(), [](const HalfEdge& x, const HalfEdge& y) {
      return x.key != y.key ? x.key < y.key : x.slot < y.slot;
    });
    edge_normals.resize(nt);
    for (std::size_t i = 0; i < half_edges.size();) {
      std::size_t j = i;
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      for (; j < half_edges.size() && half_edges[j].key == half_edges[i].key; ++j)
        sum += face_normals[half_edges[j].slot / 3];
      for (std::size_t k = i; k < j; ++k) edge_normals[half_edges[k].slot / 3][half_edges[k].slot % 3] = sum;
      i = j;
    }
  }
};

namespace {

struct PointQueryState {
  const TriangleRecord* records;
  Eigen::Vector3d p;
  double margin;
  double best = std::numeric_limits<double>::infinity();
  std::uint32_t best_triangle = 0;
  bool found = false;
  Eigen::Vector3d best_point = Eigen::Vector3d::Zero();
};

// Embree calls this for every triangle whose bounds meet the query sphere. The distance is
// evaluated exactly in double precision; the sphere shrinks to the best distance plus the
// rounding margin, so the winner is the exact nearest triangle (lowest index on ties).
bool visit_triangle(RTCPointQueryFunctionArguments* args) {
  auto* state = static_cast<PointQueryState*>(args->userPtr);
  const std::uint32_t t = args->primID;
  // Embree visits every triangle of a leaf whose box meets the sphere; most cannot win, and their
  // planes show it. A triangle farther than the best is never closer, so skipping it is exact; the slack (the
  // rounding margin and 1e-9 relative) keeps ties, settled by the lowest index.
  const TriangleRecord& record = state->records[t];
  const double reach = state->best * (1 + 1e-9) + state->margin;
  if (record.squared_distance_bound(state->p) > reach * reach) return false;
  const Eigen::Vector3d q = morph::closest_point_on_triangle(state->p, record.a, record.b, record.c);
  const double d = (state->p - q).norm();
  if (d < state->best || (d == state->best && t < state->best_triangle)) {
    state->best = d;
    state->best_triangle = t;
    state->best_point = q;
    state->found = true;
  }
  const float radius = round_up_to_float(state->best + state->margin);
  if (radius < args->query->radius) {
    args->query->radius = radius;
    return true;
  }
  return false;
}

}  // namespace

SurfaceQuery::SurfaceQuery(morph::TriangleMesh mesh) : impl_(std::make_unique<Impl>()) {
  mesh.validate("SurfaceQuery");
  impl_->mesh = std::move(mesh);
  const morph::TriangleMesh& m = impl_->mesh;
  for (const Eigen::Vector3d& v : m.vertices)
    impl_->coordinate_scale = std::max(impl_->coordinate_scale, v.cwiseAbs().maxCoeff());
  if (!std::isfinite(impl_->coordinate_scale))
    throw morph::InputError("SurfaceQuery: the mesh has a non-finite vertex coordinate");

  impl_->device = rtcNewDevice(nullptr);
  if (!impl_->device)
    throw morph::GeometryError("SurfaceQuery: cannot create an Embree device (error " +
                               std::to_string(static_cast<int>(rtcGetDeviceError(nullptr))) + ")");
  rtcSetDeviceErrorFunction(impl_->device, record_embree_error, &impl_->errors);
  impl_->scene = rtcNewScene(impl_->device);
  impl_->check("rtcNewScene");
  // Robust mode: watertight ray-triangle tests, so rays through shared edges and vertices hit.
  rtcSetSceneFlags(impl_->scene, RTC_SCENE_FLAG_ROBUST);
  if (!m.triangles.empty()) {
    RTCGeometry geometry = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    impl_->check("rtcNewGeometry");
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), m.vertices.size()));
    auto* indices = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(std::uint32_t), m.triangles.size()));
    if (!vertices || !indices) {
      rtcReleaseGeometry(geometry);
      impl_->check("rtcSetNewGeometryBuffer");
      throw morph::GeometryError("SurfaceQuery: Embree could not allocate the mesh buffers");
    }
    for (std::size_t i = 0; i < m.vertices.size(); ++i)
      for (int k = 0; k < 3; ++k) vertices[3 * i + k] = static_cast<float>(m.vertices[i][k]);
    impl_->records.resize(m.triangles.size());
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
      const morph::Triangle& tri = m.triangles[t];
      impl_->records[t] = TriangleRecord::of(m.vertices[tri[0]], m.vertices[tri[1]], m.vertices[tri[2]]);
      for (int k = 0; k < 3; ++k) indices[3 * t + k] = tri[k];
    }
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(impl_->scene, geometry);
    rtcReleaseGeometry(geometry);
    impl_->check("attaching the mesh");
  }
  rtcCommitScene(impl_->scene);
  impl_->check("rtcCommitScene");
}

SurfaceQuery::~SurfaceQuery() = default;
SurfaceQuery::SurfaceQuery(SurfaceQuery&&) noexcept = default;
SurfaceQuery& SurfaceQuery::operator=(SurfaceQuery&&) noexcept = default;

const morph::TriangleMesh& SurfaceQuery::mesh() const {
  return impl_->mesh;
}

ClosestPoint SurfaceQuery::closest_point(const Eigen::Vector3d& p, double max_distance) const {
  return closest_point(p, max_distance, kNoHint);
}

ClosestPoint SurfaceQuery::closest_point(const Eigen::Vector3d& p, double max_distance,
                                         std::uint32_t hint_triangle) const {
  ClosestPoint result;
  const morph::TriangleMesh& m = impl_->mesh;
  if (m.triangles.empty() || !p.allFinite()) return result;
  PointQueryState state{impl_->records.data(), p, impl_->margin(p)};
  double radius = max_distance;
  if (hint_triangle < m.triangles.size()) {
    // Start from the hint: the search then only visits triangles that can beat or tie it.
    const morph::Triangle& tri = m.triangles[hint_triangle];
    const Eigen::Vector3d q =
        morph::closest_point_on_triangle(p, m.vertices[tri[0]], m.vertices[tri[1]], m.vertices[tri[2]]);
    const double d = (p - q).norm();
    if (d <= max_distance) {
      state.best = d;
      state.best_triangle = hint_triangle;
      state.best_point = q;
      state.found = true;
      radius = d;
    }
  }
  RTCPointQuery query;
  query.x = static_cast<float>(p.x());
  query.y = static_cast<float>(p.y());
  query.z = static_cast<float>(p.z());
  query.time = 0.f;
  query.radius = round_up_to_float(radius + state.margin);
  RTCPointQueryContext context;
  rtcInitPointQueryContext(&context);
  rtcPointQuery(impl_->scene, &query, &context, visit_triangle, &state);
  if (!state.found || state.best > max_distance) return result;
  result.found = true;
  result.distance = state.best;
  result.point = state.best_point;
  result.triangle = state.best_triangle;
  return result;
}

void SurfaceQuery::prepare_sides() const {
  // Isolated: while this thread waits for the parallel work inside, it must not pick up another
  // task of an enclosing loop that would call side() and wait on this very call_once.
  std::call_once(impl_->normals_once,
                 [this] { tbb::this_task_arena::isolate([this] { impl_->build_normals(); }); });
}

double SurfaceQuery::side(const Eigen::Vector3d& p, const ClosestPoint& closest) const {
  prepare_sides();
  const morph::TriangleMesh& m = impl_->mesh;
  const morph::Triangle& tri = m.triangles[closest.triangle];
  const Eigen::Vector3d& a = m.vertices[tri[0]];
  const Eigen::Vector3d& b = m.vertices[tri[1]];
  const Eigen::Vector3d& c = m.vertices[tri[2]];
  const Eigen::Vector3d& q = closest.point;
  Eigen::Vector3d normal = impl_->face_normals[closest.triangle];
  const double twice_area = (b - a).cross(c - a).norm();
  if (twice_area > 0) {
    // The feature holding q (face, edge or vertex) picks the pseudo-normal; barycentric weights
    // below 1e-9 count as zero (q on an edge is computed with rounding, not exactly on it).
    const double w[3] = {(b - q).cross(c - q).norm() / twice_area, (c - q).cross(a - q).norm() / twice_area,
                         (a - q).cross(b - q).norm() / twice_area};
    constexpr double kZero = 1e-9;
    int zeros = 0, nonzero = -1;
    for (int k = 0; k < 3; ++k) {
      if (w[k] < kZero)
        ++zeros;
      else
        nonzero = k;
    }
    if (zeros == 2 && nonzero >= 0) {
      normal = impl_->vertex_normals[tri[nonzero]];
    } else if (zeros == 1) {
      for (int k = 0; k < 3; ++k)
        if (w[k] < kZero) normal = impl_->edge_normals[closest.triangle][(k + 1) % 3];  // edge opposite k
    }
  }
  return (p - q).dot(normal) < 0.0 ? -1.0 : 1.0;
}

double SurfaceQuery::signed_distance(const Eigen::Vector3d& p, ClosestPoint* closest,
                                     double max_distance) const {
  const ClosestPoint cp = closest_point(p, max_distance);
  if (closest) *closest = cp;
  if (!cp.found) return std::numeric_limits<double>::infinity();
  return side(p, cp) * cp.distance;
}

RayHit SurfaceQuery::first_hit(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, double t_min,
                               double t_max) const {
  RayHit result;
  if (impl_->mesh.triangles.empty() || !origin.allFinite() || !direction.allFinite() || direction.isZero(0))
    return result;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rayhit;
  rayhit.ray.org_x = static_cast<float>(origin.x());
  rayhit.ray.org_y = static_cast<float>(origin.y());
  rayhit.ray.org_z = static_cast<float>(origin.z());
  rayhit.ray.dir_x = static_cast<float>(direction.x());
  rayhit.ray.dir_y = static_cast<float>(direction.y());
  rayhit.ray.dir_z = static_cast<float>(direction.z());
  rayhit.ray.tnear = static_cast<float>(std::max(0.0, t_min));
  rayhit.ray.tfar = std::isfinite(t_max) ? round_up_to_float(t_max) : std::numeric_limits<float>::infinity();
  rayhit.ray.time = 0.f;
  rayhit.ray.mask = 0xffffffffu;
  rayhit.ray.id = 0;
  rayhit.ray.flags = 0;
  rayhit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rayhit.hit.primID = RTC_INVALID_GEOMETRY_ID;
  rayhit.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->scene, &context, &rayhit);
  if (rayhit.hit.geomID == RTC_INVALID_GEOMETRY_ID) return result;
  const morph::TriangleMesh& m = impl_->mesh;
  const morph::Triangle& tri = m.triangles[rayhit.hit.primID];
  const Eigen::Vector3d& a = m.vertices[tri[0]];
  const Eigen::Vector3d normal = (m.vertices[tri[1]] - a).cross(m.vertices[tri[2]] - a);
  const double denominator = normal.dot(direction);
  double t = rayhit.ray.tfar;
  // Refine the float hit against the triangle's exact plane; the refined value can leave
  // [t_min, t_max] only by float rounding, so it is clamped back.
  if (denominator != 0) t = std::clamp(normal.dot(a - origin) / denominator, std::max(0.0, t_min), t_max);
  result.hit = true;
  result.t = t;
  result.point = origin + t * direction;
  result.triangle = rayhit.hit.primID;
  result.u = rayhit.hit.u;
  result.v = rayhit.hit.v;
  return result;
}

RayHit SurfaceQuery::nearest_hit_both_ways(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                                           double max_distance) const {
  const double length = direction.norm();
  if (!(length > 0)) return {};
  const Eigen::Vector3d unit = direction / length;
  RayHit forward = first_hit(origin, unit, 0.0, max_distance);
  RayHit backward = first_hit(origin, -unit, 0.0, max_distance);
  if (backward.hit && (!forward.hit || backward.t < forward.t)) {
    backward.t = -backward.t;
    return backward;
  }
  return forward;
}

}  // namespace raytest
