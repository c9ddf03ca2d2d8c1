// SPDX-License-Identifier: Apache-2.0
// Mesh files. Every file is read whole through morph::read_regular_file (regular files only,
// length checked) and written through morph::write_file_atomically (temporary file, checked,
// renamed). STL and OBJ are read by the checked readers of stl_obj_readers.cpp and written by
// OpenMesh's writers, bridged straight from morph::TriangleMesh by an exporter so that no
// half-edge structure sits in between (OpenMesh's TriMesh would split non-manifold edges by
// duplicating vertices and drop faces with a repeated vertex, hiding exactly what
// `morphmill mesh-info` is meant to report).
//
// PLY is read and written by the small code path below instead of OpenMesh's PLY module, because
// OpenMesh 9.0 cannot do what MorphMill needs of it (checked against its source and by experiment):
//  - its PLY writer always declares `property float x/y/z`, and its reader converts positions to
//    float even when the file holds doubles, so PLY positions would lose double precision;
//  - in ASCII mode it writes uchar custom properties (our `patch_kind`) as raw bytes instead of
//    decimal text, and reads them back as characters ('2' becomes 50), so ASCII PLY files with face
//    tags are neither valid PLY nor readable from other tools.
// The PLY code handles the general format (ASCII and both binary byte orders, any element and
// property layout, list properties) and keeps what MorphMill uses; docs/mesh-io.md has the details.
#include <fmt/format.h>
#include <morph/exceptions.h>
#include <morph/file_io.h>
#include <morphmill/mesh_io.h>

#include <stdexcept>

#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/exporter/BaseExporter.hh>
#include <OpenMesh/Core/System/omstream.hh>
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iostream>
#include <iterator>
#include <limits>
#include <mutex>
#include <optional>
#include <sstream>

#include "io/stl_obj_readers.h"

namespace morphmill {

namespace {

using morph::InputError;
using morph::IoError;
using morph::TriangleMesh;

enum class MeshFormat { Ply, Stl, Obj };

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return s;
}

MeshFormat format_of(const std::string& path) {
  const std::size_t slash = path.find_last_of("/\\");
  const std::size_t dot = path.find_last_of('.');
  const std::string extension = (dot == std::string::npos || (slash != std::string::npos && dot < slash))
                                    ? ""
                                    : lower(path.substr(dot));
  if (extension == ".ply") return MeshFormat::Ply;
  if (extension == ".stl") return MeshFormat::Stl;
  if (extension == ".obj") return MeshFormat::Obj;
  throw InputError(path + ": unknown mesh format" +
                   (extension.empty() ? std::string(" (no file extension)") : " '" + extension + "'") +
                   "; expected .ply, .stl or .obj");
}

// Positions must be finite for every later computation; reject NaN/inf with the vertex index.
void check_finite(const TriangleMesh& mesh, const std::string& path) {
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
    if (!mesh.vertices[v].allFinite())
      throw InputError(path + ": vertex " + std::to_string(v) +
                       " has a coordinate that is not a finite number");
}

// ------------------------------------------------------------------------------------------------
// OpenMesh bridge (STL, OBJ)

// OpenMesh's readers and writers are singletons with mutable state and report problems on the
// global omerr/omlog streams: one call at a time, with those streams captured so that the
// library prints nothing and the captured text can go into the exception message.
std::mutex& openmesh_mutex() {
  static std::mutex mutex;
  return mutex;
}

class CapturedOpenMeshLog {
 public:
  // OpenMesh's multiplexing streams never free a target they disconnect (mostream.hh), so the
  // streams are redirected once for the process, into one buffer that each call empties, rather
  // than connected and disconnected around every call (a leak per mesh read or written).
  CapturedOpenMeshLog() {
    static std::once_flag redirected;
    std::call_once(redirected, [] {
      for (OpenMesh::mostream* s : streams()) {
        for (std::ostream* target : {&std::cerr, &std::clog, &std::cout}) s->disconnect(*target);
        s->connect(text());
      }
    });
    clear();
  }
  ~CapturedOpenMeshLog() { clear(); }
  CapturedOpenMeshLog(const CapturedOpenMeshLog&) = delete;
  CapturedOpenMeshLog& operator=(const CapturedOpenMeshLog&) = delete;

  /// The captured lines that report a problem; progress chatter ("[STLWriter] : write file") is
  /// left out.
  std::string errors() {
    for (OpenMesh::mostream* s : streams()) s->flush();
    std::istringstream lines(text().str());
    std::string line, kept;
    while (std::getline(lines, line)) {
      const std::string l = lower(line);
      if (l.find("error") != std::string::npos || l.find("warning") != std::string::npos ||
          l.find("cannot") != std::string::npos || l.find("invalid") != std::string::npos ||
          l.find("fail") != std::string::npos) {
        if (!kept.empty()) kept += "; ";
        kept += line;
      }
    }
    return kept;
  }

 private:
  static std::vector<OpenMesh::mostream*> streams() { return {&::omerr(), &::omlog(), &::omout()}; }
  /// Where OpenMesh's streams write, for the life of the process; used under openmesh_mutex().
  static std::ostringstream& text() {
    static std::ostringstream* captured = new std::ostringstream;  // outlives OpenMesh's streams
    return *captured;
  }
  static void clear() {
    for (OpenMesh::mostream* s : streams()) s->flush();
    text().str("");
    text().clear();
  }
};

// Presents a TriangleMesh to OpenMesh's writers (positions, triangles, face normals).
class TriangleMeshExporter final : public OpenMesh::IO::BaseExporter {
 public:
  explicit TriangleMeshExporter(const TriangleMesh& mesh) : mesh_(mesh) {}

  OpenMesh::Vec3f point(OpenMesh::VertexHandle vh) const override { return OpenMesh::Vec3f(pointd(vh)); }
  OpenMesh::Vec3d pointd(OpenMesh::VertexHandle vh) const override {
    const Eigen::Vector3d& p = mesh_.vertices[vh.idx()];
    return {p.x(), p.y(), p.z()};
  }
  bool is_point_double() const override { return true; }
  OpenMesh::Vec3f normal(OpenMesh::VertexHandle) const override { return {0, 0, 0}; }
  OpenMesh::Vec3d normald(OpenMesh::VertexHandle) const override { return {0, 0, 0}; }
  bool is_normal_double() const override { return true; }
  OpenMesh::Vec3uc color(OpenMesh::VertexHandle) const override { return {0, 0, 0}; }
  OpenMesh::Vec4uc colorA(OpenMesh::VertexHandle) const override { return {0, 0, 0, 255}; }
  OpenMesh::Vec3ui colori(OpenMesh::VertexHandle) const override { return {0, 0, 0}; }
  OpenMesh::Vec4ui colorAi(OpenMesh::VertexHandle) const override { return {0, 0, 0, 255}; }
  OpenMesh::Vec3f colorf(OpenMesh::VertexHandle) const override { return {0, 0, 0}; }
  OpenMesh::Vec4f colorAf(OpenMesh::VertexHandle) const override { return {0, 0, 0, 1}; }
  OpenMesh::Vec2f texcoord(OpenMesh::VertexHandle) const override { return {0, 0}; }
  OpenMesh::Vec2f texcoord(OpenMesh::HalfedgeHandle) const override { return {0, 0}; }
  OpenMesh::Attributes::StatusInfo status(OpenMesh::VertexHandle) const override { return {}; }
  unsigned int get_vhandles(OpenMesh::FaceHandle fh,
                            std::vector<OpenMesh::VertexHandle>& vhandles) const override {
    const morph::Triangle& t = mesh_.triangles[fh.idx()];
    vhandles = {OpenMesh::VertexHandle(int(t[0])), OpenMesh::VertexHandle(int(t[1])),
                OpenMesh::VertexHandle(int(t[2]))};
    return 3;
  }
  OpenMesh::HalfedgeHandle getHeh(OpenMesh::FaceHandle, OpenMesh::VertexHandle) const override {
    return OpenMesh::HalfedgeHandle();
  }
  unsigned int get_face_texcoords(std::vector<OpenMesh::Vec2f>&) const override { return 0; }
  OpenMesh::Vec3f normal(OpenMesh::FaceHandle fh) const override { return OpenMesh::Vec3f(normald(fh)); }
  OpenMesh::Vec3d normald(OpenMesh::FaceHandle fh) const override {
    const Eigen::Vector3d n = morph::face_normal(mesh_, std::size_t(fh.idx()));
    return {n.x(), n.y(), n.z()};
  }
  OpenMesh::Vec3uc color(OpenMesh::FaceHandle) const override { return {0, 0, 0}; }
  OpenMesh::Vec4uc colorA(OpenMesh::FaceHandle) const override { return {0, 0, 0, 255}; }
  OpenMesh::Vec3ui colori(OpenMesh::FaceHandle) const override { return {0, 0, 0}; }
  OpenMesh::Vec4ui colorAi(OpenMesh::FaceHandle) const override { return {0, 0, 0, 255}; }
  OpenMesh::Vec3f colorf(OpenMesh::FaceHandle) const override { return {0, 0, 0}; }
  OpenMesh::Vec4f colorAf(OpenMesh::FaceHandle) const override { return {0, 0, 0, 1}; }
  OpenMesh::Attributes::StatusInfo status(OpenMesh::FaceHandle) const override { return {}; }
  OpenMesh::Vec3uc color(OpenMesh::EdgeHandle) const override { return {0, 0, 0}; }
  OpenMesh::Vec4uc colorA(OpenMesh::EdgeHandle) const override { return {0, 0, 0, 255}; }
  OpenMesh::Vec3ui colori(OpenMesh::EdgeHandle) const override { return {0, 0, 0}; }
  OpenMesh::Vec4ui colorAi(OpenMesh::EdgeHandle) const override { return {0, 0, 0, 255}; }
  OpenMesh::Vec3f colorf(OpenMesh::EdgeHandle) const override { return {0, 0, 0}; }
  OpenMesh::Vec4f colorAf(OpenMesh::EdgeHandle) const override { return {0, 0, 0, 1}; }
  OpenMesh::Attributes::StatusInfo status(OpenMesh::EdgeHandle) const override { return {}; }
  int get_halfedge_id(OpenMesh::VertexHandle) override { return -1; }
  int get_halfedge_id(OpenMesh::FaceHandle) override { return -1; }
  int get_next_halfedge_id(OpenMesh::HalfedgeHandle) override { return -1; }
  int get_to_vertex_id(OpenMesh::HalfedgeHandle) override { return -1; }
  int get_face_id(OpenMesh::HalfedgeHandle) override { return -1; }
  OpenMesh::Attributes::StatusInfo status(OpenMesh::HalfedgeHandle) const override { return {}; }
  std::size_t n_vertices() const override { return mesh_.vertices.size(); }
  std::size_t n_faces() const override { return mesh_.triangles.size(); }
  std::size_t n_edges() const override { return 0; }
  bool is_triangle_mesh() const override { return true; }
  bool has_face_normals() const override { return true; }

 private:
  const TriangleMesh& mesh_;
};

void write_with_openmesh(const TriangleMesh& mesh, const std::string& path, MeshFormat format, bool binary) {
  TriangleMeshExporter exporter(mesh);
  OpenMesh::IO::Options options;
  if (format == MeshFormat::Stl && binary) options += OpenMesh::IO::Options::Binary;
  bool ok = false;
  std::string openmesh_errors;
  std::ostringstream bytes(std::ios::binary);
  {
    std::lock_guard<std::mutex> lock(openmesh_mutex());
    CapturedOpenMeshLog log;
    // OpenMesh's STL and OBJ writers hold positions in float: 9 significant digits round-trip them.
    ok = OpenMesh::IO::IOManager().write(bytes, format == MeshFormat::Stl ? "stl" : "obj", exporter, options,
                                         std::numeric_limits<float>::max_digits10);
    openmesh_errors = log.errors();
  }
  if (!ok || !bytes)
    throw IoError("cannot write '" + path + "'" + (openmesh_errors.empty() ? "" : ": " + openmesh_errors));
  morph::write_file_atomically(path, bytes.str());
}

// ------------------------------------------------------------------------------------------------
// PLY

enum class PlyType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

std::optional<PlyType> ply_type(const std::string& name) {
  if (name == "char" || name == "int8") return PlyType::Int8;
  if (name == "uchar" || name == "uint8") return PlyType::UInt8;
  if (name == "short" || name == "int16") return PlyType::Int16;
  if (name == "ushort" || name == "uint16") return PlyType::UInt16;
  if (name == "int" || name == "int32") return PlyType::Int32;
  if (name == "uint" || name == "uint32") return PlyType::UInt32;
  if (name == "float" || name == "float32") return PlyType::Float32;
  if (name == "double" || name == "float64") return PlyType::Float64;
  return std::nullopt;
}

std::size_t size_of(PlyType t) {
  switch (t) {
    case PlyType::Int8:
    case PlyType::UInt8:
      return 1;
    case PlyType::Int16:
    case PlyType::UInt16:
      return 2;
    case PlyType::Int32:
    case PlyType::UInt32:
    case PlyType::Float32:
      return 4;
    case PlyType::Float64:
      return 8;
  }
  return 0;
}

bool is_floating(PlyType t) {
  return t == PlyType::Float32 || t == PlyType::Float64;
}

std::pair<double, double> integer_range(PlyType t) {
  switch (t) {
    case PlyType::Int8:
      return {-128, 127};
    case PlyType::UInt8:
      return {0, 255};
    case PlyType::Int16:
      return {-32768, 32767};
    case PlyType::UInt16:
      return {0, 65535};
    case PlyType::Int32:
      return {-2147483648.0, 2147483647.0};
    case PlyType::UInt32:
      return {0, 4294967295.0};
    default:
      break;
  }
  return {-std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
}

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::Float32;
  bool is_list = false;
  PlyType count_type = PlyType::UInt8;
};

struct PlyElement {
  std::string name;
  std::size_t count = 0;
  std::vector<PlyProperty> properties;
};

enum class PlyEncoding { Ascii, BinaryLittleEndian, BinaryBigEndian };

struct PlyHeader {
  PlyEncoding encoding = PlyEncoding::Ascii;
  std::vector<PlyElement> elements;
  std::size_t body_offset = 0;  // byte offset of the first data byte
  std::size_t lines = 0;        // header lines, for ASCII line numbers
};

std::vector<std::string> split_words(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> words;
  for (std::string w; in >> w;) words.push_back(w);
  return words;
}

PlyHeader parse_ply_header(const std::string& data, const std::string& path) {
  PlyHeader header;
  std::size_t pos = 0;
  bool saw_format = false;
  auto next_line = [&](std::string& line) {
    if (pos >= data.size()) return false;
    std::size_t end = data.find('\n', pos);
    if (end == std::string::npos) end = data.size();
    line = data.substr(pos, end - pos);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    pos = std::min(end + 1, data.size());
    ++header.lines;
    return true;
  };
  std::string line;
  if (!next_line(line) || line != "ply")
    throw InputError(path + ": not a PLY file (it does not start with 'ply')");
  while (true) {
    if (!next_line(line)) throw InputError(path + ": PLY header has no 'end_header'");
    const std::string where = path + ": header line " + std::to_string(header.lines) + ": ";
    const std::vector<std::string> w = split_words(line);
    if (w.empty() || w[0] == "comment" || w[0] == "obj_info") continue;
    if (w[0] == "end_header") break;
    if (w[0] == "format") {
      if (w.size() != 3) throw InputError(where + "expected 'format <encoding> 1.0'");
      if (w[1] == "ascii")
        header.encoding = PlyEncoding::Ascii;
      else if (w[1] == "binary_little_endian")
        header.encoding = PlyEncoding::BinaryLittleEndian;
      else if (w[1] == "binary_big_endian")
        header.encoding = PlyEncoding::BinaryBigEndian;
      else
        throw InputError(where + "unknown PLY format '" + w[1] + "'");
      saw_format = true;
    } else if (w[0] == "element") {
      std::size_t count = 0;
      if (w.size() != 3 || std::from_chars(w[2].data(), w[2].data() + w[2].size(), count).ec != std::errc())
        throw InputError(where + "expected 'element <name> <count>'");
      header.elements.push_back({w[1], count, {}});
    } else if (w[0] == "property") {
      if (header.elements.empty()) throw InputError(where + "property before any element");
      PlyProperty p;
      if (w.size() == 5 && w[1] == "list") {
        const auto count_type = ply_type(w[2]);
        const auto item_type = ply_type(w[3]);
        if (!count_type || !item_type || is_floating(*count_type))
          throw InputError(where + "bad list property types '" + w[2] + " " + w[3] + "'");
        p = {w[4], *item_type, true, *count_type};
      } else if (w.size() == 3) {
        const auto type = ply_type(w[1]);
        if (!type) throw InputError(where + "unknown property type '" + w[1] + "'");
        p = {w[2], *type, false, PlyType::UInt8};
      } else {
        throw InputError(where + "expected 'property <type> <name>' or 'property list <type> <type> <name>'");
      }
      header.elements.back().properties.push_back(p);
    } else {
      throw InputError(where + "unexpected '" + w[0] + "' in the PLY header");
    }
  }
  if (!saw_format) throw InputError(path + ": PLY header has no 'format' line");
  header.body_offset = pos;
  return header;
}

// Reads the values of the PLY body one at a time, ASCII or binary; `where()` locates errors.
class PlyBodyReader {
 public:
  PlyBodyReader(const std::string& data, const PlyHeader& header, const std::string& path)
      : data_(data), pos_(header.body_offset), encoding_(header.encoding), line_(header.lines), path_(path) {}

  void begin_record() {
    if (encoding_ != PlyEncoding::Ascii) return;
    // Records are one per line; blank lines are tolerated.
    do {
      if (pos_ >= data_.size()) throw error("unexpected end of file");
      std::size_t end = data_.find('\n', pos_);
      if (end == std::string::npos) end = data_.size();
      line_text_ = std::string_view(data_).substr(pos_, end - pos_);
      pos_ = std::min(end + 1, data_.size());
      ++line_;
    } while (line_text_.find_first_not_of(" \t\r") == std::string_view::npos);
    cursor_ = 0;
  }

  void end_record() {
    if (encoding_ != PlyEncoding::Ascii) return;
    if (line_text_.find_first_not_of(" \t\r", cursor_) != std::string_view::npos)
      throw error("more values than the header declares");
  }

  double value(PlyType type, const std::string& property) {
    double v = encoding_ == PlyEncoding::Ascii ? ascii_value(property) : binary_value(type);
    if (!is_floating(type)) {
      const auto [lo, hi] = integer_range(type);
      if (v != std::floor(v) || v < lo || v > hi)
        throw error("property '" + property + "': " + fmt::format("{}", v) +
                    " is not a valid integer of its type");
    }
    return v;
  }

  InputError error(const std::string& what) const {
    const std::string where =
        encoding_ == PlyEncoding::Ascii ? "line " + std::to_string(line_) : "byte " + std::to_string(pos_);
    return InputError(path_ + ": " + where + ": " + what);
  }

 private:
  double ascii_value(const std::string& property) {
    const std::size_t start = line_text_.find_first_not_of(" \t\r", cursor_);
    if (start == std::string_view::npos) throw error("missing value for property '" + property + "'");
    std::size_t end = line_text_.find_first_of(" \t\r", start);
    if (end == std::string_view::npos) end = line_text_.size();
    const char* first = line_text_.data() + start;
    const char* last = line_text_.data() + end;
    if (first != last && *first == '+') ++first;
    double v = 0.0;
    const auto result = std::from_chars(first, last, v);
    if (result.ec != std::errc() || result.ptr != last)
      throw error("property '" + property + "': '" + std::string(line_text_.substr(start, end - start)) +
                  "' is not a number");
    cursor_ = end;
    return v;
  }

  double binary_value(PlyType type) {
    const std::size_t n = size_of(type);
    if (pos_ + n > data_.size()) throw error("unexpected end of file");
    unsigned char bytes[8];
    std::memcpy(bytes, data_.data() + pos_, n);
    pos_ += n;
    const bool file_little = encoding_ == PlyEncoding::BinaryLittleEndian;
    const std::uint16_t probe = 1;
    const bool host_little = *reinterpret_cast<const unsigned char*>(&probe) == 1;
    if (file_little != host_little) std::reverse(bytes, bytes + n);
    switch (type) {
      case PlyType::Int8:
        return double(static_cast<std::int8_t>(bytes[0]));
      case PlyType::UInt8:
        return double(bytes[0]);
      case PlyType::Int16:
        return double(load<std::int16_t>(bytes));
      case PlyType::UInt16:
        return double(load<std::uint16_t>(bytes));
      case PlyType::Int32:
        return double(load<std::int32_t>(bytes));
      case PlyType::UInt32:
        return double(load<std::uint32_t>(bytes));
      case PlyType::Float32:
        return double(load<float>(bytes));
      case PlyType::Float64:
        return load<double>(bytes);
    }
    return 0.0;
  }

  template <class T>
  static T load(const unsigned char* bytes) {
    T v;
    std::memcpy(&v, bytes, sizeof(T));
    return v;
  }

  const std::string& data_;
  std::size_t pos_;
  PlyEncoding encoding_;
  std::size_t line_;
  std::string path_;
  std::string_view line_text_;
  std::size_t cursor_ = 0;
};

/// Refuses element counts that the file's bytes cannot hold, before anything is allocated for
/// them: every record takes at least one byte, so the records of all elements together cannot
/// outnumber the bytes after the header. (A claim within that bound but still too long for the
/// data is reported by the body reader at the line or byte where the data ends; what it
/// allocates meanwhile is bounded by a small multiple of the file's size.)
void check_counts_fit(const PlyHeader& header, std::size_t file_bytes, const std::string& path) {
  const std::size_t available = file_bytes - std::min(file_bytes, header.body_offset);
  std::size_t records = 0;
  for (const PlyElement& e : header.elements) {
    if (e.count == 0) continue;
    if (e.properties.empty())
      throw InputError(path + ": PLY element '" + e.name + "' declares " + std::to_string(e.count) +
                       " records but no properties");
    records = e.count > available ? available + 1 : records + e.count;
    if (records > available)
      throw InputError(path + ": unexpected end of file: the PLY header declares " + std::to_string(e.count) +
                       " '" + e.name + "' records, but only " + std::to_string(available) +
                       " bytes follow the header (every record takes at least one byte)");
  }
}

// What each vertex/face property becomes.
enum class Role { Skip, X, Y, Z, Red, Green, Blue, Scalar, Indices, Kind, Source, Line };

TriangleMesh read_ply(const std::string& data, const std::string& path) {
  const PlyHeader header = parse_ply_header(data, path);
  const PlyElement* vertex_element = nullptr;
  const PlyElement* face_element = nullptr;
  for (const PlyElement& e : header.elements) {
    if (e.name == "vertex") vertex_element = &e;
    if (e.name == "face") face_element = &e;
  }
  if (!vertex_element) throw InputError(path + ": PLY file has no 'vertex' element");
  if (!face_element)
    throw InputError(path + ": PLY file has no 'face' element (a point cloud is not a mesh)");

  check_counts_fit(header, data.size(), path);

  TriangleMesh mesh;
  PlyBodyReader body(data, header, path);
  const std::size_t vertex_count = vertex_element->count;
  for (const PlyElement& element : header.elements) {
    std::vector<Role> roles(element.properties.size(), Role::Skip);
    std::vector<std::size_t> scalar_slot(element.properties.size(), 0);
    bool has_x = false, has_y = false, has_z = false, has_color = false, has_indices = false,
         has_tags = false;
    if (&element == vertex_element) {
      for (std::size_t i = 0; i < roles.size(); ++i) {
        const PlyProperty& p = element.properties[i];
        if (p.is_list) continue;
        if (p.name == "x")
          roles[i] = Role::X, has_x = true;
        else if (p.name == "y")
          roles[i] = Role::Y, has_y = true;
        else if (p.name == "z")
          roles[i] = Role::Z, has_z = true;
        else if (p.name == "red")
          roles[i] = Role::Red, has_color = true;
        else if (p.name == "green")
          roles[i] = Role::Green, has_color = true;
        else if (p.name == "blue")
          roles[i] = Role::Blue, has_color = true;
        else if (p.name == "nx" || p.name == "ny" || p.name == "nz" || p.name == "alpha")
          continue;
        else if (is_floating(p.type)) {
          roles[i] = Role::Scalar;
          scalar_slot[i] = mesh.scalars.size();
          mesh.scalars.push_back({p.name, std::vector<double>(element.count, 0.0)});
        }
      }
      if (!has_x || !has_y || !has_z) throw InputError(path + ": PLY vertex element lacks x, y or z");
      mesh.vertices.resize(element.count, Eigen::Vector3d::Zero());
      if (has_color) mesh.colors.resize(element.count, morph::Color{0, 0, 0});
    } else if (&element == face_element) {
      for (std::size_t i = 0; i < roles.size(); ++i) {
        const PlyProperty& p = element.properties[i];
        if (p.is_list && (p.name == "vertex_indices" || p.name == "vertex_index"))
          roles[i] = Role::Indices, has_indices = true;
        else if (!p.is_list && p.name == "patch_kind")
          roles[i] = Role::Kind, has_tags = true;
        else if (!p.is_list && p.name == "source")
          roles[i] = Role::Source, has_tags = true;
        else if (!p.is_list && p.name == "line")
          roles[i] = Role::Line, has_tags = true;
      }
      if (!has_indices) throw InputError(path + ": PLY face element lacks 'vertex_indices'");
      mesh.triangles.reserve(element.count);
      if (has_tags) mesh.tags.reserve(element.count);
    }

    std::vector<std::uint32_t> polygon;
    for (std::size_t r = 0; r < element.count; ++r) {
      body.begin_record();
      morph::FaceTag tag;
      auto checked_int32 = [&](double v, const char* property) {
        if (!(v >= -2147483648.0 && v <= 2147483647.0 && v == std::floor(v)))
          throw body.error("face " + std::to_string(r) + ": " + property + " " + fmt::format("{}", v) +
                           " is not a 32-bit integer");
        return std::int32_t(v);
      };
      polygon.clear();
      for (std::size_t i = 0; i < element.properties.size(); ++i) {
        const PlyProperty& p = element.properties[i];
        if (p.is_list) {
          const double n = body.value(p.count_type, p.name);
          for (double k = 0; k < n; ++k) {
            const double item = body.value(p.type, p.name);
            if (roles[i] == Role::Indices) {
              // Written so that NaN (a float index list) fails too; found by the PLY fuzzer.
              if (!(item >= 0 && item < double(vertex_count) && item == std::floor(item)))
                throw body.error("face " + std::to_string(r) + " refers to vertex " +
                                 fmt::format("{}", item) + " but there are " + std::to_string(vertex_count) +
                                 " vertices");
              polygon.push_back(std::uint32_t(item));
            }
          }
          continue;
        }
        const double v = body.value(p.type, p.name);
        auto color_channel = [&](double value) -> std::uint8_t {
          const double c = is_floating(p.type) ? std::round(value * 255.0) : value;
          if (!(c >= 0 && c <= 255))
            throw body.error("colour '" + p.name + "' of vertex " + std::to_string(r) + " is out of range");
          return std::uint8_t(c);
        };
        switch (roles[i]) {
          case Role::X:
            mesh.vertices[r].x() = v;
            break;
          case Role::Y:
            mesh.vertices[r].y() = v;
            break;
          case Role::Z:
            mesh.vertices[r].z() = v;
            break;
          case Role::Red:
            mesh.colors[r][0] = color_channel(v);
            break;
          case Role::Green:
            mesh.colors[r][1] = color_channel(v);
            break;
          case Role::Blue:
            mesh.colors[r][2] = color_channel(v);
            break;
          case Role::Scalar:
            mesh.scalars[scalar_slot[i]].values[r] = v;
            break;
          case Role::Kind:
            if (v < 0 || v > double(morph::PatchKind::Reference))
              throw body.error("face " + std::to_string(r) + ": patch_kind " + fmt::format("{}", v) +
                               " is not a known patch kind (0 to " +
                               std::to_string(int(morph::PatchKind::Reference)) + ")");
            tag.kind = morph::PatchKind(int(v));
            break;
          case Role::Source:
            tag.source = checked_int32(v, "source");
            break;
          case Role::Line:
            tag.line = checked_int32(v, "line");
            break;
          default:
            break;
        }
      }
      body.end_record();
      if (&element == face_element) {
        if (polygon.size() < 3)
          throw body.error("face " + std::to_string(r) + " has " + std::to_string(polygon.size()) +
                           " vertices; a face needs at least 3");
        for (std::size_t k = 1; k + 1 < polygon.size(); ++k) {
          mesh.triangles.push_back({polygon[0], polygon[k], polygon[k + 1]});
          if (has_tags) mesh.tags.push_back(tag);
        }
      }
    }
  }
  if (mesh.triangles.empty()) throw InputError(path + ": PLY file has no faces");
  check_finite(mesh, path);
  return mesh;
}

bool valid_property_name(const std::string& name) {
  if (name.empty()) return false;
  for (unsigned char c : name)
    if (std::isspace(c) || !std::isprint(c)) return false;
  static const char* const reserved[] = {"x", "y", "z", "nx", "ny", "nz", "red", "green", "blue", "alpha"};
  for (const char* r : reserved)
    if (name == r) return false;
  return true;
}

template <class T>
void append_little_endian(std::string& out, T value) {
  unsigned char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  const std::uint16_t probe = 1;
  if (*reinterpret_cast<const unsigned char*>(&probe) != 1) std::reverse(bytes, bytes + sizeof(T));
  out.append(reinterpret_cast<const char*>(bytes), sizeof(T));
}

void write_ply(const TriangleMesh& mesh, const std::string& path, bool binary,
               const std::vector<std::string>& comments) {
  for (const morph::VertexScalar& s : mesh.scalars)
    if (!valid_property_name(s.name))
      throw InputError(
          path + ": vertex scalar name '" + s.name +
          "' cannot be a PLY property (empty, contains spaces, or clashes with x/y/z/nx/ny/nz/colour)");
  const bool has_colors = !mesh.colors.empty();
  const bool has_tags = !mesh.tags.empty();
  std::string out;
  out.reserve(64 * mesh.vertices.size() + 32 * mesh.triangles.size() + 512);
  out += "ply\n";
  out += binary ? "format binary_little_endian 1.0\n" : "format ascii 1.0\n";
  out += "comment written by morphmill: double positions; face tags patch_kind/source/line\n";
  for (const std::string& comment : comments) {
    if (comment.find_first_of("\r\n") != std::string::npos)
      throw std::invalid_argument(path + ": a PLY comment cannot hold a line break");
    out += "comment " + comment + "\n";
  }
  out += fmt::format("element vertex {}\n", mesh.vertices.size());
  out += "property double x\nproperty double y\nproperty double z\n";
  if (has_colors) out += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  for (const morph::VertexScalar& s : mesh.scalars) out += "property double " + s.name + "\n";
  out += fmt::format("element face {}\n", mesh.triangles.size());
  out += "property list uchar int vertex_indices\n";
  if (has_tags) out += "property uchar patch_kind\nproperty int source\nproperty int line\n";
  out += "end_header\n";

  auto inserter = std::back_inserter(out);
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    const Eigen::Vector3d& p = mesh.vertices[v];
    if (binary) {
      for (int k = 0; k < 3; ++k) append_little_endian(out, p[k]);
      if (has_colors)
        for (int k = 0; k < 3; ++k) out.push_back(char(mesh.colors[v][k]));
      for (const morph::VertexScalar& s : mesh.scalars) append_little_endian(out, s.values[v]);
    } else {
      // fmt's "{}" prints the shortest text that reads back to the same double.
      fmt::format_to(inserter, "{} {} {}", p.x(), p.y(), p.z());
      if (has_colors)
        fmt::format_to(inserter, " {} {} {}", mesh.colors[v][0], mesh.colors[v][1], mesh.colors[v][2]);
      for (const morph::VertexScalar& s : mesh.scalars) fmt::format_to(inserter, " {}", s.values[v]);
      out.push_back('\n');
    }
  }
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const morph::Triangle& tri = mesh.triangles[t];
    if (binary) {
      out.push_back(char(3));
      for (std::uint32_t v : tri) append_little_endian(out, std::int32_t(v));
      if (has_tags) {
        out.push_back(char(mesh.tags[t].kind));
        append_little_endian(out, mesh.tags[t].source);
        append_little_endian(out, mesh.tags[t].line);
      }
    } else {
      fmt::format_to(inserter, "3 {} {} {}", tri[0], tri[1], tri[2]);
      if (has_tags)
        fmt::format_to(inserter, " {} {} {}", int(mesh.tags[t].kind), mesh.tags[t].source, mesh.tags[t].line);
      out.push_back('\n');
    }
  }
  morph::write_file_atomically(path, out);
}

}  // namespace

morph::TriangleMesh read_mesh(const std::string& path) {
  format_of(path);  // before reading: a wrong name costs nothing
  return read_mesh_bytes(morph::read_regular_file(path, "mesh file"), path);
}

morph::TriangleMesh read_mesh_bytes(const std::string& data, const std::string& name) {
  const MeshFormat format = format_of(name);
  TriangleMesh mesh = format == MeshFormat::Ply   ? read_ply(data, name)
                      : format == MeshFormat::Stl ? read_stl_bytes(data, name)
                                                  : read_obj_bytes(data, name);
  check_finite(mesh, name);
  return mesh;
}

void write_mesh(const morph::TriangleMesh& mesh, const std::string& path, const MeshWriteOptions& options,
                const std::vector<std::string>& comments) {
  const MeshFormat format = format_of(path);
  mesh.validate(path);
  if (mesh.vertices.size() > std::size_t(std::numeric_limits<std::int32_t>::max()))
    throw morph::LimitError(path + ": too many vertices for a mesh file");
  if (format == MeshFormat::Ply)
    write_ply(mesh, path, options.binary, comments);
  else
    write_with_openmesh(mesh, path, format, options.binary);
}

}  // namespace morphmill
