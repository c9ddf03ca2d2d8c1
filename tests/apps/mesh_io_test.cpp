// SPDX-License-Identifier: Apache-2.0
// Mesh file round trips (every format, binary and ASCII), what each format keeps, and the errors.
#include <gtest/gtest.h>
#include <morph/exceptions.h>
#include <morph/topology.h>
#include <morphmill/mesh_io.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>

#include "apps/command_support.h"
#include "common/test_meshes.h"

namespace {

namespace fs = std::filesystem;
using morph::TriangleMesh;

class MeshIo : public morphmill_test::ScratchDirTest {
 protected:
};

// Positions that no float holds exactly, so a float32 path would show.
TriangleMesh tagged_mesh() {
  TriangleMesh mesh =
      morphmill_test::box({0.1, 1.0 / 3.0, -2.7182818284590451}, {10.000000000000002, 7.3, 1e-9});
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    mesh.tags.push_back(
        {morph::PatchKind(t % 6), std::int32_t(t * 1000003 % 2147483647) - 7, std::int32_t(t + 1)});
  mesh.tags[3].source = -2147483647 - 1;  // extremes of int32
  mesh.tags[4].line = 2147483647;
  morph::VertexScalar deviation{"deviation", {}}, distance{"signed_distance", {}};
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    deviation.values.push_back(std::sqrt(2.0) * double(v) - 1e-300);
    distance.values.push_back(-1.0 / double(v + 3));
    mesh.colors.push_back({std::uint8_t(v * 37), std::uint8_t(255 - v), std::uint8_t(v == 0 ? 0 : 255)});
  }
  mesh.scalars = {deviation, distance};
  return mesh;
}

void expect_same_topology(const morph::TopologyReport& a, const morph::TopologyReport& b,
                          double volume_tolerance) {
  EXPECT_EQ(a.vertices, b.vertices);
  EXPECT_EQ(a.unreferenced_vertices, b.unreferenced_vertices);
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_EQ(a.degenerate_triangles, b.degenerate_triangles);
  EXPECT_EQ(a.edges, b.edges);
  EXPECT_EQ(a.boundary_edges, b.boundary_edges);
  EXPECT_EQ(a.non_manifold_edges, b.non_manifold_edges);
  EXPECT_EQ(a.inconsistent_edges, b.inconsistent_edges);
  EXPECT_EQ(a.non_manifold_vertices, b.non_manifold_vertices);
  EXPECT_EQ(a.components, b.components);
  EXPECT_EQ(a.euler_characteristic, b.euler_characteristic);
  EXPECT_NEAR(a.volume, b.volume, volume_tolerance);
}

/// The value a float32 format keeps of x.
double as_float(double x) {
  return double(float(x));
}

TEST_F(MeshIo, PlyBinaryAndAsciiKeepEverythingExactly) {
  const TriangleMesh original = tagged_mesh();
  for (bool binary : {true, false}) {
    SCOPED_TRACE(binary ? "binary" : "ascii");
    const std::string file = path(binary ? "b.ply" : "a.ply");
    morphmill::write_mesh(original, file, {binary});
    const TriangleMesh back = morphmill::read_mesh(file);
    ASSERT_EQ(back.vertices.size(), original.vertices.size());
    for (std::size_t v = 0; v < original.vertices.size(); ++v) {
      EXPECT_EQ(back.vertices[v], original.vertices[v]) << "vertex " << v;  // bit-exact doubles
      EXPECT_EQ(back.colors[v], original.colors[v]) << "colour " << v;
    }
    EXPECT_EQ(back.triangles, original.triangles);
    EXPECT_EQ(back.tags, original.tags);
    ASSERT_EQ(back.scalars.size(), 2u);
    for (std::size_t s = 0; s < 2; ++s) {
      EXPECT_EQ(back.scalars[s].name, original.scalars[s].name);
      EXPECT_EQ(back.scalars[s].values, original.scalars[s].values);
    }
    const morph::TopologyReport before = morph::topology_report(original);
    const morph::TopologyReport after = morph::topology_report(back);
    expect_same_topology(before, after, 0.0);
    EXPECT_EQ(before.volume, after.volume);
  }
}

TEST_F(MeshIo, PlyAsciiIsTextWithDecimalTags) {
  // Other tools must be able to read our ASCII PLY: tags are decimal numbers, not raw bytes.
  TriangleMesh mesh = morphmill_test::box({0, 0, 0}, {1, 1, 1});
  mesh.tags.assign(mesh.triangles.size(), {morph::PatchKind::SideSweep, 42, 17});
  morphmill::write_mesh(mesh, path("t.ply"), {false});
  std::ifstream in(path("t.ply"));
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("property uchar patch_kind\nproperty int source\nproperty int line\n"),
            std::string::npos);
  EXPECT_NE(text.find("property double x\n"), std::string::npos);
  EXPECT_NE(text.find("3 0 2 3 3 42 17\n"), std::string::npos);
}

TEST_F(MeshIo, PlyWithoutOptionalDataStaysWithout) {
  const TriangleMesh cube = morphmill_test::box({0, 0, 0}, {2, 3, 4});
  morphmill::write_mesh(cube, path("c.ply"));
  const TriangleMesh back = morphmill::read_mesh(path("c.ply"));
  EXPECT_TRUE(back.tags.empty());
  EXPECT_TRUE(back.colors.empty());
  EXPECT_TRUE(back.scalars.empty());
  EXPECT_EQ(back.vertices, cube.vertices);
  EXPECT_DOUBLE_EQ(morph::enclosed_volume(back), 24.0);
}

TEST_F(MeshIo, ReadsForeignPlyLayouts) {
  // Float positions and scalars, float colours, an extra element, a quad, a vertex_index list,
  // tag properties in a different order, CRLF line ends and a comment.
  const std::string file =
      write_text("foreign.ply",
                 "ply\r\nformat ascii 1.0\r\ncomment from elsewhere\r\n"
                 "element vertex 4\r\nproperty float x\r\nproperty float y\r\n"
                 "property float z\r\nproperty float quality\r\nproperty float red\r\n"
                 "property float green\r\nproperty float blue\r\nproperty int flags\r\n"
                 "element material 1\r\nproperty list uchar float values\r\n"
                 "element face 1\r\nproperty int line\r\nproperty list uchar uint vertex_index\r\n"
                 "property short patch_kind\r\nend_header\r\n"
                 "0 0 0 0.5 1 0 0 7\r\n1 0 0 0.25 0 1 0 7\r\n1 1 0 -1.5 0 0 1 7\r\n"
                 "0 1 0 2 0.5 0.5 0.5 7\r\n"
                 "3 0.1 0.2 0.3\r\n"
                 "99 4 0 1 2 3 +2\r\n");
  const TriangleMesh mesh = morphmill::read_mesh(file);
  ASSERT_EQ(mesh.vertices.size(), 4u);
  EXPECT_EQ(mesh.vertices[2], Eigen::Vector3d(1, 1, 0));
  ASSERT_EQ(mesh.triangles.size(), 2u);  // the quad, as a fan
  EXPECT_EQ(mesh.triangles[0], (morph::Triangle{0, 1, 2}));
  EXPECT_EQ(mesh.triangles[1], (morph::Triangle{0, 2, 3}));
  ASSERT_EQ(mesh.tags.size(), 2u);
  EXPECT_EQ(mesh.tags[1].kind, morph::PatchKind::CutSurface);
  EXPECT_EQ(mesh.tags[1].line, 99);
  EXPECT_EQ(mesh.tags[1].source, -1);  // absent: the FaceTag default
  ASSERT_EQ(mesh.scalars.size(), 1u);  // the int property 'flags' is not a scalar
  EXPECT_EQ(mesh.scalars[0].name, "quality");
  EXPECT_EQ(mesh.scalars[0].values, (std::vector<double>{0.5, 0.25, -1.5, 2}));
  ASSERT_EQ(mesh.colors.size(), 4u);
  EXPECT_EQ(mesh.colors[0], (morph::Color{255, 0, 0}));
  EXPECT_EQ(mesh.colors[3], (morph::Color{128, 128, 128}));  // 0.5 * 255 rounds to 128
}

TEST_F(MeshIo, ReadsBigEndianBinaryPly) {
  std::string data =
      "ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty double x\nproperty double y\n"
      "property double z\nelement face 1\nproperty list uchar int vertex_indices\nproperty uchar patch_kind\n"
      "end_header\n";
  auto put_be = [&](const void* value, std::size_t n) {
    const unsigned char* bytes = static_cast<const unsigned char*>(value);
    for (std::size_t i = 0; i < n; ++i) data.push_back(char(bytes[n - 1 - i]));  // this host is little-endian
  };
  const double coords[9] = {0.1, 0.2, 0.3, 1.0 / 3.0, 0, 0, 0, 1, 1e-9};
  for (double c : coords) put_be(&c, 8);
  data.push_back(char(3));
  for (std::int32_t i : {0, 1, 2}) put_be(&i, 4);
  data.push_back(char(4));
  const std::string file = write_text("be.ply", data);
  const TriangleMesh mesh = morphmill::read_mesh(file);
  ASSERT_EQ(mesh.vertices.size(), 3u);
  EXPECT_EQ(mesh.vertices[0], Eigen::Vector3d(0.1, 0.2, 0.3));
  EXPECT_EQ(mesh.vertices[1], Eigen::Vector3d(1.0 / 3.0, 0, 0));
  EXPECT_EQ(mesh.vertices[2], Eigen::Vector3d(0, 1, 1e-9));
  ASSERT_EQ(mesh.tags.size(), 1u);
  EXPECT_EQ(mesh.tags[0].kind, morph::PatchKind::FrontSweep);
}

TEST_F(MeshIo, StlBinaryAndAsciiKeepFloatPositionsAndMergeVertices) {
  const TriangleMesh original = morphmill_test::torus(3.0, 1.0 / 3.0, 24, 10);
  for (bool binary : {true, false}) {
    SCOPED_TRACE(binary ? "binary" : "ascii");
    const std::string file = path(binary ? "b.stl" : "a.stl");
    morphmill::write_mesh(original, file, {binary});
    const TriangleMesh back = morphmill::read_mesh(file);
    // STL repeats every corner per facet; the reader merges coincident corners again.
    ASSERT_EQ(back.vertices.size(), original.vertices.size());
    ASSERT_EQ(back.triangles.size(), original.triangles.size());
    // Facet order is kept; every corner equals the original rounded to float, exactly.
    for (std::size_t t = 0; t < original.triangles.size(); ++t)
      for (int k = 0; k < 3; ++k)
        for (int axis = 0; axis < 3; ++axis)
          ASSERT_EQ(back.vertices[back.triangles[t][k]][axis],
                    as_float(original.vertices[original.triangles[t][k]][axis]))
              << "triangle " << t << " corner " << k << " axis " << axis;
    expect_same_topology(morph::topology_report(original), morph::topology_report(back), 1e-5);
  }
}

TEST_F(MeshIo, ObjKeepsIndicesAndFloatPositions) {
  const TriangleMesh original = tagged_mesh();
  morphmill::write_mesh(original, path("m.obj"));
  const TriangleMesh back = morphmill::read_mesh(path("m.obj"));
  ASSERT_EQ(back.vertices.size(), original.vertices.size());
  for (std::size_t v = 0; v < original.vertices.size(); ++v)
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(back.vertices[v][k], as_float(original.vertices[v][k])) << "vertex " << v << " axis " << k;
  EXPECT_EQ(back.triangles, original.triangles);
  EXPECT_TRUE(back.tags.empty());  // OBJ cannot hold them
  expect_same_topology(morph::topology_report(original), morph::topology_report(back), 1e-5);
}

TEST_F(MeshIo, ObjPolygonsBecomeTriangleFans) {
  const std::string file =
      write_text("quad.obj",
                 "# a square and a pentagon\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv -1 0.5 0\n"
                 "vn 0 0 1\nf 1//1 2//1 3//1 4//1\nf 4 5 1\n");
  const TriangleMesh mesh = morphmill::read_mesh(file);
  ASSERT_EQ(mesh.triangles.size(), 3u);
  EXPECT_EQ(mesh.triangles[0], (morph::Triangle{0, 1, 2}));
  EXPECT_EQ(mesh.triangles[1], (morph::Triangle{0, 2, 3}));
  EXPECT_EQ(mesh.triangles[2], (morph::Triangle{3, 4, 0}));
  EXPECT_DOUBLE_EQ(morph::surface_area(mesh), 1.5);
}

TEST_F(MeshIo, NonManifoldMeshesSurviveEveryFormat) {
  // The reader must not repair what mesh-info is meant to report.
  for (const std::string name : {"fin.ply", "fin.stl", "fin.obj", "bow.ply", "bow.stl", "bow.obj"}) {
    SCOPED_TRACE(name);
    const TriangleMesh original =
        name.rfind("fin", 0) == 0 ? morphmill_test::fin() : morphmill_test::bow_tie();
    morphmill::write_mesh(original, path(name));
    const morph::TopologyReport before = morph::topology_report(original);
    const morph::TopologyReport after = morph::topology_report(morphmill::read_mesh(path(name)));
    expect_same_topology(before, after, 1e-12);
    EXPECT_EQ(after.non_manifold_edges + after.non_manifold_vertices, name.rfind("fin", 0) == 0 ? 3u : 1u);
  }
}

TEST_F(MeshIo, ReadsTheBundledMeshes) {
  const std::string data = MORPHMILL_TEST_DATA;
  for (const char* name : {"meshes/cube.stl", "meshes/cube.ply", "meshes/tetra.obj", "meshes/tetra.ply"}) {
    SCOPED_TRACE(name);
    const morph::TopologyReport r = morph::topology_report(morphmill::read_mesh(data + "/" + name));
    EXPECT_TRUE(r.closed_manifold());
    EXPECT_EQ(r.euler_characteristic, 2);
    EXPECT_EQ(r.components, 1u);
    EXPECT_GT(r.volume, 0.0);
  }
  EXPECT_DOUBLE_EQ(morph::topology_report(morphmill::read_mesh(data + "/meshes/cube.stl")).volume, 1000.0);
  EXPECT_DOUBLE_EQ(morph::topology_report(morphmill::read_mesh(data + "/meshes/tetra.ply")).volume,
                   1000.0 / 6.0);
}

// ---- errors

template <class Error>
std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  } catch (const std::exception& e) {
    return std::string("wrong exception type: ") + e.what();
  }
  return "no exception";
}

TEST_F(MeshIo, MissingFileIsAnIoErrorNamingIt) {
  const std::string file = path("absent.stl");
  const std::string message = error_of<morph::IoError>([&] { morphmill::read_mesh(file); });
  EXPECT_NE(message.find(file), std::string::npos) << message;
  EXPECT_NE(message.find("No such file"), std::string::npos) << message;
  EXPECT_NE(error_of<morph::IoError>([&] { morphmill::read_mesh(path("absent.ply")); }).find("absent.ply"),
            std::string::npos);
}

TEST_F(MeshIo, UnknownExtensionIsAnInputError) {
  const std::string message = error_of<morph::InputError>([&] { morphmill::read_mesh(path("part.off")); });
  EXPECT_NE(message.find("part.off"), std::string::npos) << message;
  EXPECT_NE(message.find("'.off'"), std::string::npos) << message;
  EXPECT_NE(message.find(".ply, .stl or .obj"), std::string::npos) << message;
  EXPECT_NE(error_of<morph::InputError>([&] {
              morphmill::write_mesh(morphmill_test::fin(), path("noext"));
            }).find("no file extension"),
            std::string::npos);
}

TEST_F(MeshIo, GarbageIsAnInputErrorNamingTheFile) {
  const std::string garbage = "this is not a mesh\n\x01\x02\x03 at all\n";
  for (const char* name : {"g.ply", "g.stl", "g.obj"}) {
    const std::string file = write_text(name, garbage);
    const std::string message = error_of<morph::InputError>([&] { morphmill::read_mesh(file); });
    EXPECT_EQ(message.find(file), 0u) << message;
  }
  EXPECT_NE(error_of<morph::InputError>([&] { morphmill::read_mesh(path("g.ply")); }).find("not a PLY file"),
            std::string::npos);
  EXPECT_NE(error_of<morph::InputError>([&] { morphmill::read_mesh(path("g.obj")); }).find("no triangles"),
            std::string::npos);
  const std::string empty = write_text("empty.stl", "");
  EXPECT_NE(error_of<morph::InputError>([&] { morphmill::read_mesh(empty); }).find(empty), std::string::npos);
}

TEST_F(MeshIo, PlyContentErrorsNameFileLineAndProblem) {
  const std::string head =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\n"
      "element face 1\nproperty list uchar int vertex_indices\nproperty uchar patch_kind\nend_header\n";
  const std::string vertices = "0 0 0\n1 0 0\n0 1 0\n";
  struct Case {
    std::string body, expected;
  };
  const Case cases[] = {
      {vertices + "2 0 1 5\n", "line 14: face 0 has 2 vertices; a face needs at least 3"},
      {vertices + "3 0 1 3 5\n", "line 14: face 0 refers to vertex 3 but there are 3 vertices"},
      {vertices + "3 0 1 2 9\n", "line 14: face 0: patch_kind 9 is not a known patch kind (0 to 5)"},
      {vertices + "3 0 1 2 300\n", "line 14: property 'patch_kind': 300 is not a valid integer of its type"},
      {"0 0 0\n1 zero 0\n0 1 0\n3 0 1 2 5\n", "line 12: property 'y': 'zero' is not a number"},
      {"0 0 0\n1 0\n", "line 12: missing value for property 'z'"},
      {"0 0 0\n1 0 0 7\n", "line 12: more values than the header declares"},
      {vertices, "unexpected end of file"},
      {"0 0 0\n1 0 0\n0 nan 0\n3 0 1 2 5\n", "vertex 2 has a coordinate that is not a finite number"},
  };
  int i = 0;
  for (const Case& c : cases) {
    const std::string file = write_text("bad" + std::to_string(i++) + ".ply", head + c.body);
    const std::string message = error_of<morph::InputError>([&] { morphmill::read_mesh(file); });
    EXPECT_EQ(message.find(file + ": "), 0u) << message;
    EXPECT_NE(message.find(c.expected), std::string::npos)
        << "expected '" << c.expected << "' in: " << message;
  }
  const std::string truncated = write_text(
      "trunc.ply",
      "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
      "property float z\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n"
      "\x00\x00\x00\x00");
  EXPECT_NE(
      error_of<morph::InputError>([&] { morphmill::read_mesh(truncated); }).find("unexpected end of file"),
      std::string::npos);
  const std::string no_faces = write_text(
      "cloud.ply",
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
      "end_header\n0 0 0\n");
  EXPECT_NE(error_of<morph::InputError>([&] { morphmill::read_mesh(no_faces); }).find("point cloud"),
            std::string::npos);
  const std::string bad_header =
      write_text("hdr.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\n");
  EXPECT_NE(error_of<morph::InputError>([&] {
              morphmill::read_mesh(bad_header);
            }).find("header line 4: unknown property type 'quad'"),
            std::string::npos);
}

TEST_F(MeshIo, ObjFaceErrors) {
  const std::string file = write_text("bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n");
  const std::string message = error_of<morph::InputError>([&] { morphmill::read_mesh(file); });
  EXPECT_EQ(message.find(file), 0u) << message;
}

TEST_F(MeshIo, WriteErrors) {
  const std::string file = (dir_ / "no_such_dir" / "x.ply").string();
  const std::string message =
      error_of<morph::IoError>([&] { morphmill::write_mesh(morphmill_test::fin(), file); });
  EXPECT_NE(message.find(file), std::string::npos) << message;
  EXPECT_NE(error_of<morph::IoError>([&] {
              morphmill::write_mesh(morphmill_test::fin(), (dir_ / "no_such_dir" / "x.stl").string());
            }).find("x.stl"),
            std::string::npos);
  TriangleMesh named = morphmill_test::fin();
  named.scalars.push_back({"bad name", std::vector<double>(named.vertices.size(), 0.0)});
  EXPECT_NE(
      error_of<morph::InputError>([&] { morphmill::write_mesh(named, path("s.ply")); }).find("'bad name'"),
      std::string::npos);
  TriangleMesh broken = morphmill_test::fin();
  broken.triangles.push_back({0, 1, 99});
  EXPECT_THROW(morphmill::write_mesh(broken, path("broken.ply")), morph::InputError);
}

}  // namespace
