// SPDX-License-Identifier: Apache-2.0
// The Python module `morphmill` (pybind11): the public C++ API of morphmill/morphmill.h, with
// numpy arrays for meshes (vertices N x 3 float64, triangles M x 3 uint32, tags M x 3 int32) and
// for samples (positions, normals N x 3, values N). Long computations release the GIL.
#include <morph/exceptions.h>
#include <morphmill/morphmill.h>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstring>
#include <string>

namespace py = pybind11;

namespace {

using Array3d = py::array_t<double, py::array::c_style | py::array::forcecast>;
using Array3u = py::array_t<std::uint32_t, py::array::c_style | py::array::forcecast>;

py::array_t<double> points_array(const std::vector<Eigen::Vector3d>& points) {
  py::array_t<double> array({static_cast<py::ssize_t>(points.size()), py::ssize_t(3)});
  auto out = array.mutable_unchecked<2>();
  for (std::size_t i = 0; i < points.size(); ++i)
    for (int k = 0; k < 3; ++k) out(i, k) = points[i][k];
  return array;
}

py::array_t<double> doubles_array(const std::vector<double>& values) {
  py::array_t<double> array(static_cast<py::ssize_t>(values.size()));
  if (!values.empty()) std::memcpy(array.mutable_data(), values.data(), values.size() * sizeof(double));
  return array;
}

py::array_t<std::uint32_t> triangles_array(const morph::TriangleMesh& mesh) {
  py::array_t<std::uint32_t> array({static_cast<py::ssize_t>(mesh.triangles.size()), py::ssize_t(3)});
  auto out = array.mutable_unchecked<2>();
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i)
    for (int k = 0; k < 3; ++k) out(i, k) = mesh.triangles[i][k];
  return array;
}

// One row (kind, source, line) per triangle; (0, -1, 0) everywhere when the mesh has no tags.
py::array_t<std::int32_t> tags_array(const morph::TriangleMesh& mesh) {
  py::array_t<std::int32_t> array({static_cast<py::ssize_t>(mesh.triangles.size()), py::ssize_t(3)});
  auto out = array.mutable_unchecked<2>();
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    const morph::FaceTag tag = mesh.tags.empty() ? morph::FaceTag{} : mesh.tags[i];
    out(i, 0) = static_cast<std::int32_t>(tag.kind);
    out(i, 1) = tag.source;
    out(i, 2) = tag.line;
  }
  return array;
}

morph::TriangleMesh mesh_from_arrays(const Array3d& vertices, const Array3u& triangles) {
  if (vertices.ndim() != 2 || vertices.shape(1) != 3)
    throw morph::InputError("vertices: expected an array of shape (N, 3)");
  if (triangles.ndim() != 2 || triangles.shape(1) != 3)
    throw morph::InputError("triangles: expected an array of shape (M, 3)");
  morph::TriangleMesh mesh;
  const auto v = vertices.unchecked<2>();
  const auto t = triangles.unchecked<2>();
  mesh.vertices.resize(v.shape(0));
  for (py::ssize_t i = 0; i < v.shape(0); ++i) mesh.vertices[i] = {v(i, 0), v(i, 1), v(i, 2)};
  mesh.triangles.resize(t.shape(0));
  for (py::ssize_t i = 0; i < t.shape(0); ++i) {
    for (int k = 0; k < 3; ++k) {
      if (t(i, k) >= mesh.vertices.size())
        throw morph::InputError("triangles[" + std::to_string(i) + "]: vertex index " +
                                std::to_string(t(i, k)) + " out of range (" +
                                std::to_string(mesh.vertices.size()) + " vertices)");
      mesh.triangles[i][k] = t(i, k);
    }
  }
  return mesh;
}

py::object json_to_python(const nlohmann::json& json) {
  return py::module_::import("json").attr("loads")(json.dump());
}

raytest::DeviationMode deviation_mode(const std::string& name) {
  if (name == "unsigned") return raytest::DeviationMode::Unsigned;
  if (name == "signed") return raytest::DeviationMode::Signed;
  if (name == "ray") return raytest::DeviationMode::Ray;
  throw morph::InputError("mode: '" + name + "' is not one of unsigned, signed, ray");
}

}  // namespace

PYBIND11_MODULE(morphmill, m) {
  m.doc() =
      "MorphMill: what a milling tool leaves of a part, exactly, and how exact it is.\n"
      "Lengths are in the job's units (mm or inch), volumes in those units cubed.";

  py::register_exception<morph::InputError>(m, "InputError", PyExc_ValueError);
  py::register_exception<morph::IoError>(m, "IoError", PyExc_OSError);
  py::register_exception<morph::LimitError>(m, "LimitError", PyExc_MemoryError);
  py::register_exception<morph::GeometryError>(m, "GeometryError", PyExc_RuntimeError);
  py::register_exception<morph::Interrupted>(m, "Interrupted", PyExc_KeyboardInterrupt);

  m.def("version", &morphmill::version, "MorphMill's version, as `morphmill --version` prints it.");

  py::class_<morph::Job>(m, "Job", "A milling job: stock, tools, ordered paths, tolerance (job units).")
      .def_readonly("name", &morph::Job::name)
      .def_readonly("file", &morph::Job::file)
      .def_property_readonly("units", [](const morph::Job& job) { return morph::to_string(job.units); })
      .def_readonly("tolerance", &morph::Job::tolerance)
      .def_property_readonly("move_count", &morph::Job::move_count)
      .def_property_readonly("warnings",
                             [](const morph::Job& job) {
                               std::vector<std::string> out;
                               for (const morph::Warning& w : job.warnings)
                                 out.push_back(w.file + ":" + std::to_string(w.line) + ": " + w.message);
                               return out;
                             })
      .def(
          "describe", [](const morph::Job& job) { return json_to_python(morphmill::describe_job(job)); },
          "The job as understood (stock, tools, moves by kind, bounds), as `morphmill info --json`.")
      .def("__repr__", [](const morph::Job& job) {
        return "<morphmill.Job '" + job.name + "', " + std::to_string(job.move_count()) + " moves>";
      });

  m.def("load_job", &morphmill::load_job, py::arg("path"),
        "Reads a job file (JSON job or CAMotics project). Raises InputError naming the file and the "
        "JSON path or G-code line, IoError when it cannot be read.");

  py::class_<morph::TriangleMesh>(m, "Mesh",
                                  "An indexed triangle mesh; arrays are copies (vertices float64 (N, 3), "
                                  "triangles uint32 (M, 3), tags int32 (M, 3): kind, source move or "
                                  "stock face, G-code line).")
      .def(py::init(&mesh_from_arrays), py::arg("vertices"), py::arg("triangles"))
      .def_property_readonly("vertices",
                             [](const morph::TriangleMesh& mesh) { return points_array(mesh.vertices); })
      .def_property_readonly("triangles", &triangles_array)
      .def_property_readonly("tags", &tags_array)
      .def_property_readonly("vertex_count", &morph::TriangleMesh::vertex_count)
      .def_property_readonly("triangle_count", &morph::TriangleMesh::triangle_count)
      .def("topology", &morph::topology_report, "Closed? manifold? pieces, area, volume.")
      .def("__repr__", [](const morph::TriangleMesh& mesh) {
        return "<morphmill.Mesh " + std::to_string(mesh.vertex_count()) + " vertices, " +
               std::to_string(mesh.triangle_count()) + " triangles>";
      });

  m.def("read_mesh", &morphmill::read_mesh, py::arg("path"), "Reads a PLY, STL or OBJ mesh.");
  m.def(
      "write_mesh",
      [](const morph::TriangleMesh& mesh, const std::string& path) { morphmill::write_mesh(mesh, path); },
      py::arg("mesh"), py::arg("path"), "Writes a mesh (format from the extension; PLY keeps the tags).");

  py::class_<morph::TopologyReport>(m, "Topology")
      .def_readonly("vertices", &morph::TopologyReport::vertices)
      .def_readonly("triangles", &morph::TopologyReport::triangles)
      .def_readonly("boundary_edges", &morph::TopologyReport::boundary_edges)
      .def_readonly("non_manifold_edges", &morph::TopologyReport::non_manifold_edges)
      .def_readonly("components", &morph::TopologyReport::components)
      .def_readonly("euler_characteristic", &morph::TopologyReport::euler_characteristic)
      .def_readonly("volume", &morph::TopologyReport::volume)
      .def_readonly("area", &morph::TopologyReport::area)
      .def_property_readonly("closed_manifold", &morph::TopologyReport::closed_manifold);

  py::class_<morphmill::ErodeReport>(m, "ErodeReport")
      .def_readonly("mesh", &morphmill::ErodeReport::mesh)
      .def_readonly("topology", &morphmill::ErodeReport::topology)
      .def_readonly("self_intersections", &morphmill::ErodeReport::self_intersections)
      .def_property_readonly("valid", &morphmill::ErodeReport::valid)
      .def_property_readonly("seconds",
                             [](const morphmill::ErodeReport& r) { return r.stats.seconds_total; });

  m.def(
      "erode",
      [](const morph::Job& job, double tolerance) {
        morphmill::ErodeSettings settings;
        settings.tolerance = tolerance;
        return morphmill::erode(job, settings);
      },
      py::arg("job"), py::arg("tolerance") = 0.0, py::call_guard<py::gil_scoped_release>(),
      "The generator's surface of what the tool leaves of the stock, and its checks (tolerance: job "
      "units, 0 = the job's).");

  m.def("default_voxel_size", &morphmill::default_voxel_size, py::arg("job"));

  py::class_<vdb_ref::ReferenceResult>(m, "Reference")
      .def_readonly("mesh", &vdb_ref::ReferenceResult::mesh)
      .def_property_readonly("volume", &vdb_ref::ReferenceResult::volume)
      .def_property_readonly("area", &vdb_ref::ReferenceResult::area)
      .def_property_readonly("voxel_size",
                             [](const vdb_ref::ReferenceResult& r) { return r.stats.voxel_size; })
      .def_property_readonly("piece_volumes", [](const vdb_ref::ReferenceResult& r) {
        std::vector<double> volumes;
        for (const vdb_ref::ReferencePiece& piece : r.pieces) volumes.push_back(piece.volume);
        return doubles_array(volumes);
      });

  m.def(
      "reference",
      [](const morph::Job& job, double voxel_size) {
        morphmill::ReferenceSettings settings;
        settings.voxel_size = voxel_size;
        return morphmill::reference(job, settings);
      },
      py::arg("job"), py::arg("voxel_size") = 0.0, py::call_guard<py::gil_scoped_release>(),
      "The OpenVDB level-set reference at one voxel size (job units; 0 = default_voxel_size(job)).");

  py::class_<raytest::DeviationStats>(m, "DeviationStats")
      .def_readonly("count", &raytest::DeviationStats::count)
      .def_readonly("misses", &raytest::DeviationStats::misses)
      .def_readonly("min", &raytest::DeviationStats::min)
      .def_readonly("max", &raytest::DeviationStats::max)
      .def_readonly("mean", &raytest::DeviationStats::mean)
      .def_readonly("rms", &raytest::DeviationStats::rms)
      .def_readonly("max_abs", &raytest::DeviationStats::max_abs)
      .def_readonly("p50", &raytest::DeviationStats::p50)
      .def_readonly("p90", &raytest::DeviationStats::p90)
      .def_readonly("p99", &raytest::DeviationStats::p99);

  py::class_<raytest::OneSidedDeviation>(m, "Samples",
                                         "Samples of one surface measured against another: positions and "
                                         "normals (N, 3), values (N; NaN for a miss), triangles (N).")
      .def_property_readonly("positions",
                             [](const raytest::OneSidedDeviation& d) {
                               std::vector<Eigen::Vector3d> points;
                               for (const raytest::SurfaceSample& s : d.samples) points.push_back(s.position);
                               return points_array(points);
                             })
      .def_property_readonly("normals",
                             [](const raytest::OneSidedDeviation& d) {
                               std::vector<Eigen::Vector3d> normals;
                               for (const raytest::SurfaceSample& s : d.samples) normals.push_back(s.normal);
                               return points_array(normals);
                             })
      .def_property_readonly("values",
                             [](const raytest::OneSidedDeviation& d) { return doubles_array(d.values); })
      .def_property_readonly("triangles",
                             [](const raytest::OneSidedDeviation& d) {
                               py::array_t<std::uint32_t> array(static_cast<py::ssize_t>(d.samples.size()));
                               auto out = array.mutable_unchecked<1>();
                               for (std::size_t i = 0; i < d.samples.size(); ++i)
                                 out(i) = d.samples[i].triangle;
                               return array;
                             })
      .def_readonly("stats", &raytest::OneSidedDeviation::stats);

  py::class_<raytest::TwoSidedDeviation>(m, "Deviation")
      .def_readonly("a_to_b", &raytest::TwoSidedDeviation::a_to_b)
      .def_readonly("b_to_a", &raytest::TwoSidedDeviation::b_to_a)
      .def_readonly("hausdorff", &raytest::TwoSidedDeviation::hausdorff);

  m.def(
      "deviation",
      [](const morph::TriangleMesh& a, const morph::TriangleMesh& b, std::size_t face_samples,
         std::size_t edge_samples, bool vertices, std::uint64_t seed, const std::string& mode,
         double max_distance) {
        morphmill::DeviationSettings settings;
        settings.face_samples = face_samples;
        settings.edge_samples = edge_samples;
        settings.vertices = vertices;
        settings.seed = seed;
        settings.mode = deviation_mode(mode);
        settings.max_distance = max_distance;
        py::gil_scoped_release release;
        return morphmill::deviation(a, b, settings);
      },
      py::arg("a"), py::arg("b"), py::arg("face_samples") = 100000, py::arg("edge_samples") = 0,
      py::arg("vertices") = true, py::arg("seed") = 1, py::arg("mode") = "unsigned",
      py::arg("max_distance") = std::numeric_limits<double>::infinity(),
      "Samples A and B and measures each against the other (mode: unsigned, signed or ray).");

  py::class_<morphmill::VerifyReport>(m, "VerifyReport")
      .def_readonly("verdict", &morphmill::VerifyReport::verdict)
      .def_readonly("generator_within_tolerance", &morphmill::VerifyReport::generator_within_tolerance)
      .def_readonly("sides_agree", &morphmill::VerifyReport::sides_agree)
      .def_readonly("pieces_match", &morphmill::VerifyReport::pieces_match)
      .def_readonly("generator_skipped", &morphmill::VerifyReport::generator_skipped)
      .def_readonly("tolerance", &morphmill::VerifyReport::tolerance)
      .def_readonly("voxel_size", &morphmill::VerifyReport::voxel_size)
      .def_readonly("agreement_bound", &morphmill::VerifyReport::agreement_bound)
      .def_readonly("resolvable_hausdorff", &morphmill::VerifyReport::resolvable_hausdorff)
      .def_readonly("generator_mesh", &morphmill::VerifyReport::generator_mesh)
      .def_readonly("reference_mesh", &morphmill::VerifyReport::reference_mesh)
      .def_readonly("generator_to_exact", &morphmill::VerifyReport::generator_to_exact)
      .def_readonly("reference_to_exact", &morphmill::VerifyReport::reference_to_exact)
      .def_property_readonly("summary",
                             [](const morphmill::VerifyReport& r) { return json_to_python(r.summary); });

  m.def(
      "verify",
      [](const morph::Job& job, double voxel_size, double tolerance, std::size_t face_samples,
         std::uint64_t seed, bool reference_only) {
        morphmill::VerifySettings settings;
        settings.voxel_size = voxel_size;
        settings.tolerance = tolerance;
        settings.face_samples = face_samples;
        settings.seed = seed;
        settings.reference_only = reference_only;
        return morphmill::verify(job, settings);
      },
      py::arg("job"), py::arg("voxel_size") = 0.0, py::arg("tolerance") = 0.0,
      py::arg("face_samples") = 100000, py::arg("seed") = 1, py::arg("reference_only") = false,
      py::call_guard<py::gil_scoped_release>(),
      "Generator, reference and deviation on one job, with the verdict of `morphmill verify`.");
}
