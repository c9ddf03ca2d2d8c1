// SPDX-License-Identifier: Apache-2.0
#include "io/deviation_files.h"

#include <fmt/format.h>
#include <morph/file_io.h>
#include <morphmill/mesh_io.h>

#include <cstdint>
#include <cstring>
#include <stdexcept>

#include "verify/html.h"

namespace morphmill {

namespace {

const morph::VertexScalar& scalar_of(const morph::TriangleMesh& mesh, const std::string& name,
                                     const std::string& path) {
  const morph::VertexScalar* s = mesh.scalar(name);
  if (!s) throw std::invalid_argument(path + ": the mesh has no vertex scalar '" + name + "'");
  return *s;
}

// VTK XML "binary" inline data: base64 of a UInt64 byte count followed by the raw little-endian
// values (the header_type="UInt64" layout without a compressor).
template <class T>
std::string vtk_binary(const std::vector<T>& values) {
  static_assert(std::is_arithmetic_v<T>);
  const std::uint16_t probe = 1;
  if (*reinterpret_cast<const unsigned char*>(&probe) != 1)
    throw std::runtime_error("VTK XML output is written little-endian only");
  const std::uint64_t bytes = values.size() * sizeof(T);
  std::string raw(sizeof bytes + bytes, '\0');
  std::memcpy(raw.data(), &bytes, sizeof bytes);
  if (bytes) std::memcpy(raw.data() + sizeof bytes, values.data(), bytes);
  return base64(raw);
}

template <class T>
const char* vtk_type();
template <>
const char* vtk_type<double>() {
  return "Float64";
}
template <>
const char* vtk_type<std::int32_t>() {
  return "Int32";
}
template <>
const char* vtk_type<std::int64_t>() {
  return "Int64";
}
template <>
const char* vtk_type<std::uint8_t>() {
  return "UInt8";
}

template <class T>
std::string data_array(const std::string& name, const std::vector<T>& values, int components = 1,
                       const std::string& units = "") {
  std::string out =
      fmt::format("<DataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\" format=\"binary\">\n",
                  vtk_type<T>(), html_escape(name), components);
  out += vtk_binary(values) + "\n";
  // After the data: VTK's reader takes the first character data of the element as the array.
  if (!units.empty())
    out += "<InformationKey name=\"UNITS_LABEL\" location=\"vtkDataArray\">" + html_escape(units) +
           "</InformationKey>\n";
  return out + "</DataArray>\n";
}

// A vtkStringArray in ASCII: each string as its byte values, each ended by 0.
std::string string_array(const std::string& name, const std::vector<std::string>& strings) {
  std::string out =
      fmt::format("<Array type=\"String\" Name=\"{}\" NumberOfTuples=\"{}\" format=\"ascii\">\n",
                  html_escape(name), strings.size());
  for (const std::string& s : strings) {
    for (unsigned char c : s) out += fmt::format("{} ", int(c));
    out += "0\n";
  }
  return out + "</Array>\n";
}

}  // namespace

void write_deviation_ply(const morph::TriangleMesh& mesh, const std::string& scalar, const std::string& path,
                         const Provenance& provenance) {
  morph::TriangleMesh named = mesh;
  const morph::VertexScalar deviation = scalar_of(mesh, scalar, path);
  named.scalars.clear();
  named.scalars.push_back({"quality", deviation.values});
  named.scalars.push_back({"scalar_" + scalar, deviation.values});
  for (const morph::VertexScalar& s : mesh.scalars)
    if (s.name != scalar) named.scalars.push_back(s);
  std::vector<std::string> comments = provenance_lines(provenance);
  comments.push_back(
      fmt::format("deviation: vertex property 'quality' (MeshLab) = 'scalar_{}' "
                  "(CloudCompare: scalar field '{}'), signed, {}",
                  scalar, scalar, provenance.units));
  write_mesh(named, path, {}, comments);
}

void write_deviation_vtp(const morph::TriangleMesh& mesh, const std::string& scalar, const std::string& path,
                         const Provenance& provenance) {
  const morph::VertexScalar& deviation = scalar_of(mesh, scalar, path);
  std::vector<double> points;
  points.reserve(3 * mesh.vertices.size());
  for (const Eigen::Vector3d& v : mesh.vertices) points.insert(points.end(), {v.x(), v.y(), v.z()});
  std::vector<std::int64_t> connectivity, offsets;
  connectivity.reserve(3 * mesh.triangles.size());
  offsets.reserve(mesh.triangles.size());
  std::vector<double> cell_deviation;
  cell_deviation.reserve(mesh.triangles.size());
  for (const morph::Triangle& t : mesh.triangles) {
    connectivity.insert(connectivity.end(), {std::int64_t(t[0]), std::int64_t(t[1]), std::int64_t(t[2])});
    offsets.push_back(std::int64_t(connectivity.size()));
    cell_deviation.push_back((deviation.values[t[0]] + deviation.values[t[1]] + deviation.values[t[2]]) /
                             3.0);
  }

  std::string out = "<?xml version=\"1.0\"?>\n";
  out +=
      "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" "
      "header_type=\"UInt64\">\n<PolyData>\n";
  out += "<FieldData>\n" + string_array("units", {provenance.units}) +
         string_array("provenance", provenance_lines(provenance)) + "</FieldData>\n";
  out += fmt::format(
      "<Piece NumberOfPoints=\"{}\" NumberOfVerts=\"0\" NumberOfLines=\"0\" NumberOfStrips=\"0\" "
      "NumberOfPolys=\"{}\">\n",
      mesh.vertices.size(), mesh.triangles.size());
  out += "<PointData Scalars=\"" + html_escape(scalar) + "\">\n" +
         data_array(scalar, deviation.values, 1, provenance.units);
  if (!mesh.colors.empty()) {
    std::vector<std::uint8_t> colours;
    colours.reserve(3 * mesh.colors.size());
    for (const auto& c : mesh.colors) colours.insert(colours.end(), {c[0], c[1], c[2]});
    out += data_array("colour", colours, 3);
  }
  out += "</PointData>\n<CellData Scalars=\"" + html_escape(scalar) + "\">\n" +
         data_array(scalar, cell_deviation, 1, provenance.units);
  if (!mesh.tags.empty()) {
    std::vector<std::int32_t> move, line;
    std::vector<std::uint8_t> kind;
    for (const morph::FaceTag& tag : mesh.tags) {
      move.push_back(tag.source);
      line.push_back(tag.line);
      kind.push_back(std::uint8_t(tag.kind));
    }
    out += data_array("move", move) + data_array("gcode_line", line) + data_array("patch_kind", kind);
  }
  out += "</CellData>\n<Points>\n" + data_array("Points", points, 3, provenance.units) + "</Points>\n";
  out +=
      "<Polys>\n" + data_array("connectivity", connectivity) + data_array("offsets", offsets) + "</Polys>\n";
  out += "</Piece>\n</PolyData>\n</VTKFile>\n";
  morph::write_file_atomically(path, out);
}

}  // namespace morphmill
