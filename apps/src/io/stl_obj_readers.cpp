// SPDX-License-Identifier: Apache-2.0
// Checked STL and OBJ readers (see stl_obj_readers.h for why they are not OpenMesh's).
#include "io/stl_obj_readers.h"

#include <fmt/format.h>
#include <morph/exceptions.h>

#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace morphmill {

namespace {

using morph::InputError;
using morph::TriangleMesh;

/// Lines of a text file, numbered from 1, with '\r' and surrounding blanks removed.
class Lines {
 public:
  explicit Lines(std::string_view data) : data_(data) {}
  bool next(std::string_view& line) {
    if (pos_ >= data_.size()) return false;
    const std::size_t end = std::min(data_.find('\n', pos_), data_.size());
    line = data_.substr(pos_, end - pos_);
    pos_ = end + 1;
    ++number_;
    const std::size_t first = line.find_first_not_of(" \t\r\f\v");
    line = first == std::string_view::npos ? std::string_view() : line.substr(first);
    const std::size_t last = line.find_last_not_of(" \t\r\f\v");
    line = last == std::string_view::npos ? std::string_view() : line.substr(0, last + 1);
    return true;
  }
  std::size_t number() const { return number_; }

 private:
  std::string_view data_;
  std::size_t pos_ = 0;
  std::size_t number_ = 0;
};

/// The next blank-separated word of `line` (advancing it), empty at the end.
std::string_view next_word(std::string_view& line) {
  const std::size_t start = line.find_first_not_of(" \t\r\f\v");
  if (start == std::string_view::npos) {
    line = {};
    return {};
  }
  std::size_t end = line.find_first_of(" \t\r\f\v", start);
  if (end == std::string_view::npos) end = line.size();
  const std::string_view word = line.substr(start, end - start);
  line = line.substr(end);
  return word;
}

/// A finite coordinate, rounded to float32 (STL's type; OBJ positions were float in OpenMesh).
bool parse_coordinate(std::string_view word, double& out) {
  if (!word.empty() && word.front() == '+') word.remove_prefix(1);
  double v = 0.0;
  const auto result = std::from_chars(word.data(), word.data() + word.size(), v);
  if (result.ec != std::errc() || result.ptr != word.data() + word.size() || !std::isfinite(v)) return false;
  const float f = float(v);
  if (!std::isfinite(f)) return false;
  out = double(f);
  return true;
}

/// Merges corners with the same float position (+0 and -0 alike), numbering them as they appear.
class CornerMerger {
 public:
  explicit CornerMerger(TriangleMesh& mesh) : mesh_(mesh) {}
  std::uint32_t index(const Eigen::Vector3d& p) {
    std::array<std::uint32_t, 3> key{};
    for (int k = 0; k < 3; ++k) {
      const float f = float(p[k]) + 0.0f;  // -0 becomes +0
      std::memcpy(&key[k], &f, sizeof f);
    }
    const auto [it, inserted] = ids_.try_emplace(key, std::uint32_t(mesh_.vertices.size()));
    if (inserted) mesh_.vertices.push_back(p);
    return it->second;
  }

 private:
  struct Hash {
    std::size_t operator()(const std::array<std::uint32_t, 3>& k) const {
      return std::hash<std::uint64_t>()((std::uint64_t(k[0]) << 32 | k[1]) ^
                                        (std::uint64_t(k[2]) * 0x9E3779B97F4A7C15ull));
    }
  };
  TriangleMesh& mesh_;
  std::unordered_map<std::array<std::uint32_t, 3>, std::uint32_t, Hash> ids_;
};

TriangleMesh read_binary_stl(const std::string& data, const std::string& name, std::uint32_t count) {
  TriangleMesh mesh;
  CornerMerger corners(mesh);
  mesh.triangles.reserve(count);  // the length was checked: 50 bytes per triangle are present
  for (std::uint32_t t = 0; t < count; ++t) {
    const char* record = data.data() + 84 + 50 * std::size_t(t);
    morph::Triangle triangle{};
    for (int corner = 0; corner < 3; ++corner) {
      float xyz[3];
      std::memcpy(xyz, record + 12 + 12 * corner, sizeof xyz);  // STL is little-endian, as x86 is
      if (!std::isfinite(xyz[0]) || !std::isfinite(xyz[1]) || !std::isfinite(xyz[2]))
        throw InputError(name + ": binary STL triangle " + std::to_string(t) +
                         " has a coordinate that is not a finite number");
      triangle[corner] = corners.index(Eigen::Vector3d(xyz[0], xyz[1], xyz[2]));
    }
    mesh.triangles.push_back(triangle);
  }
  return mesh;
}

TriangleMesh read_ascii_stl(const std::string& data, const std::string& name) {
  TriangleMesh mesh;
  CornerMerger corners(mesh);
  Lines lines(data);
  std::string_view line;
  std::vector<std::uint32_t> loop;
  bool in_loop = false;
  auto fail = [&](const std::string& what) -> InputError {
    return InputError(name + ": line " + std::to_string(lines.number()) + ": " + what);
  };
  while (lines.next(line)) {
    const std::string_view keyword = next_word(line);
    if (keyword == "outer") {
      if (in_loop) throw fail("'outer loop' inside a loop");
      in_loop = true;
      loop.clear();
    } else if (keyword == "vertex") {
      if (!in_loop) throw fail("'vertex' outside an 'outer loop'");
      Eigen::Vector3d p;
      for (int k = 0; k < 3; ++k) {
        const std::string_view word = next_word(line);
        if (!parse_coordinate(word, p[k]))
          throw fail("vertex coordinate '" + std::string(word.substr(0, 40)) + "' is not a finite float");
      }
      loop.push_back(corners.index(p));
    } else if (keyword == "endloop") {
      if (!in_loop) throw fail("'endloop' without 'outer loop'");
      if (loop.size() < 3)
        throw fail("facet with " + std::to_string(loop.size()) + " vertices; a facet needs at least 3");
      for (std::size_t k = 1; k + 1 < loop.size(); ++k)
        mesh.triangles.push_back({loop[0], loop[k], loop[k + 1]});
      in_loop = false;
    } else if (keyword.empty() || keyword == "solid" || keyword == "facet" || keyword == "endfacet" ||
               keyword == "endsolid") {
      continue;
    } else {
      throw fail("unexpected '" + std::string(keyword.substr(0, 40)) + "' in an ASCII STL file");
    }
  }
  if (in_loop) throw InputError(name + ": ASCII STL ends inside a facet ('outer loop' without 'endloop')");
  return mesh;
}

/// A face corner `v`, `v/t`, `v//n` or `v/t/n`: the position index, 1-based or negative (relative).
std::uint32_t obj_corner(std::string_view word, std::size_t vertex_count,
                         const std::function<InputError(const std::string&)>& fail) {
  const std::string_view index = word.substr(0, word.find('/'));
  long long i = 0;
  const auto result = std::from_chars(index.data(), index.data() + index.size(), i);
  if (index.empty() || result.ec != std::errc() || result.ptr != index.data() + index.size() || i == 0)
    throw fail("face corner '" + std::string(word.substr(0, 40)) + "' has no valid vertex index");
  const long long resolved = i > 0 ? i - 1 : (long long)vertex_count + i;
  if (resolved < 0 || resolved >= (long long)vertex_count)
    throw fail("face refers to vertex " + std::to_string(i) + " but " + std::to_string(vertex_count) +
               " vertices are defined so far");
  return std::uint32_t(resolved);
}

}  // namespace

TriangleMesh read_stl_bytes(const std::string& data, const std::string& name) {
  if (data.size() >= 84) {
    std::uint32_t count = 0;
    std::memcpy(&count, data.data() + 80, 4);
    if (data.size() == 84 + 50 * std::uint64_t(count)) {
      TriangleMesh mesh = read_binary_stl(data, name, count);
      if (mesh.triangles.empty()) throw InputError(name + ": binary STL file with no triangles");
      return mesh;
    }
  }
  const std::size_t start = data.find_first_not_of(" \t\r\n");
  if (start == std::string::npos || data.compare(start, 5, "solid") != 0) {
    if (data.size() >= 84) {
      std::uint32_t count = 0;
      std::memcpy(&count, data.data() + 80, 4);
      throw InputError(name + ": not an STL file: as binary STL its header claims " + std::to_string(count) +
                       " triangles (" + std::to_string(84 + 50 * std::uint64_t(count)) +
                       " bytes) but the file has " + std::to_string(data.size()) +
                       " bytes, and it does not start with 'solid' as ASCII STL does");
    }
    throw InputError(name + ": not an STL file (" + std::to_string(data.size()) +
                     " bytes, too short for binary STL, and no 'solid' as ASCII STL starts)");
  }
  TriangleMesh mesh = read_ascii_stl(data, name);
  if (mesh.triangles.empty()) throw InputError(name + ": no triangles found in the ASCII STL file");
  return mesh;
}

TriangleMesh read_obj_bytes(const std::string& data, const std::string& name) {
  TriangleMesh mesh;
  Lines lines(data);
  std::string_view line;
  std::vector<std::uint32_t> polygon;
  const std::function<InputError(const std::string&)> fail = [&](const std::string& what) {
    return InputError(name + ": line " + std::to_string(lines.number()) + ": " + what);
  };
  while (lines.next(line)) {
    const std::string_view keyword = next_word(line);
    if (keyword == "v") {
      Eigen::Vector3d p;
      for (int k = 0; k < 3; ++k) {
        const std::string_view word = next_word(line);
        if (!parse_coordinate(word, p[k]))
          throw fail("vertex coordinate '" + std::string(word.substr(0, 40)) + "' is not a finite float");
      }
      mesh.vertices.push_back(p);
    } else if (keyword == "f") {
      polygon.clear();
      for (std::string_view word = next_word(line); !word.empty(); word = next_word(line))
        polygon.push_back(obj_corner(word, mesh.vertices.size(), fail));
      if (polygon.size() < 3)
        throw fail("face with " + std::to_string(polygon.size()) + " vertices; a face needs at least 3");
      for (std::size_t k = 1; k + 1 < polygon.size(); ++k)
        mesh.triangles.push_back({polygon[0], polygon[k], polygon[k + 1]});
    }
    // Everything else (comments, normals, texture coordinates, groups, materials) is not kept.
  }
  if (mesh.triangles.empty())
    throw InputError(name + ": no triangles found (empty file, or not an OBJ mesh)");
  return mesh;
}

}  // namespace morphmill
