// SPDX-License-Identifier: Apache-2.0
#include <morph/exceptions.h>
#include <morph/file_io.h>
#include <raytest/render.h>
#include <raytest/surface_query.h>
#include <stb/stb_image_write.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "legend.h"

namespace raytest {

View parse_view(const std::string& name) {
  if (name == "iso") return View::Iso;
  if (name == "top") return View::Top;
  if (name == "front") return View::Front;
  throw morph::InputError("unknown view '" + name + "' (expected iso, top or front)");
}

namespace {

struct Camera {
  Eigen::Vector3d direction;  // viewing direction (unit)
  Eigen::Vector3d right;
  Eigen::Vector3d up;
};

Camera camera_for(View view) {
  Camera c;
  Eigen::Vector3d up_hint(0, 0, 1);
  switch (view) {
    case View::Iso:
      c.direction = -Eigen::Vector3d(1, -1, 1).normalized();
      break;
    case View::Top:
      c.direction = Eigen::Vector3d(0, 0, -1);
      up_hint = Eigen::Vector3d(0, 1, 0);
      break;
    case View::Front:
      c.direction = Eigen::Vector3d(0, 1, 0);
      break;
  }
  c.right = c.direction.cross(up_hint).normalized();
  c.up = c.right.cross(c.direction);
  return c;
}

void fill_rect(Image& image, int x0, int y0, int x1, int y1, const morph::Color& color) {
  x0 = std::max(x0, 0);
  y0 = std::max(y0, 0);
  x1 = std::min(x1, image.width);
  y1 = std::min(y1, image.height);
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      const std::size_t i = 3 * (static_cast<std::size_t>(y) * image.width + x);
      image.rgb[i] = color[0];
      image.rgb[i + 1] = color[1];
      image.rgb[i + 2] = color[2];
    }
}

// The orthographic camera of a picture: what is framed and the size of one pixel.
struct Framing {
  Camera camera;
  Eigen::Vector3d center;
  double pixel = 1.0;
  double distance_back = 1.0;
  int view_width = 0;
};

Framing frame(const morph::TriangleMesh& mesh, const RenderOptions& options, int view_width) {
  Framing f;
  f.camera = camera_for(options.view);
  f.view_width = view_width;
  const Eigen::AlignedBox3d whole = morph::bounds(mesh);
  const Eigen::AlignedBox3d box = options.focus ? *options.focus : whole;
  f.center = box.center();
  double half_x = 0, half_y = 0;
  for (int corner = 0; corner < 8; ++corner) {
    const Eigen::Vector3d d = box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(corner)) - f.center;
    half_x = std::max(half_x, std::abs(d.dot(f.camera.right)));
    half_y = std::max(half_y, std::abs(d.dot(f.camera.up)));
  }
  // Fits the projected box with a 6% margin.
  f.pixel = 1.12 * std::max(2 * half_x / view_width, 2 * half_y / options.height);
  if (!(f.pixel > 0)) f.pixel = 1.0;
  f.distance_back = 2.0 * ((f.center - whole.center()).norm() + whole.diagonal().norm() + 1.0);
  if (options.focus) {
    // Rays start on the box's near side: walls in front of a close-up's place do not hide it.
    const Eigen::Vector3d half = 0.5 * box.sizes();
    f.distance_back = 1.05 * half.cwiseProduct(f.camera.direction).cwiseAbs().sum() + 1e-9;
  }
  return f;
}

detail::Legend legend_of(const morph::VertexScalar& scalar, const RenderOptions& options,
                         const ScalarRange& range) {
  detail::Legend legend;
  legend.color_map = options.color_map;
  legend.range = range;
  legend.title = scalar.name + (options.unit.empty() ? "" : " [" + options.unit + "]");
  legend.low_caption = options.low_caption;
  legend.high_caption = options.high_caption;
  return legend;
}

int view_width_of(const morph::TriangleMesh& mesh, const RenderOptions& options, ScalarRange* range_out) {
  if (options.scalar.empty()) return options.width;
  const morph::VertexScalar* scalar = mesh.scalar(options.scalar);
  if (!scalar) return options.width;
  const ScalarRange range = options.range ? *options.range : auto_range(scalar->values, options.symmetric);
  if (range_out) *range_out = range;
  const int panel =
      std::min(detail::legend_width(legend_of(*scalar, options, range), options.height), options.width / 2);
  return options.width - panel;
}

}  // namespace

Image render_mesh(const morph::TriangleMesh& mesh, const RenderOptions& options) {
  if (options.width < 16 || options.height < 16 || options.width > 16384 || options.height > 16384)
    throw morph::InputError("render: image size " + std::to_string(options.width) + "x" +
                            std::to_string(options.height) + " is outside 16..16384 pixels");
  const morph::VertexScalar* scalar = nullptr;
  if (!options.scalar.empty()) {
    scalar = mesh.scalar(options.scalar);
    if (!scalar) {
      std::string names;
      for (const morph::VertexScalar& s : mesh.scalars) names += (names.empty() ? "" : ", ") + s.name;
      throw morph::InputError("render: the mesh has no vertex scalar '" + options.scalar +
                              "' (it has: " + (names.empty() ? std::string("none") : names) + ")");
    }
  }
  Image image;
  image.width = options.width;
  image.height = options.height;
  image.rgb.resize(static_cast<std::size_t>(image.width) * image.height * 3);
  fill_rect(image, 0, 0, image.width, image.height, options.background);
  if (mesh.empty()) return image;

  ScalarRange range{0, 1};
  const int view_width = view_width_of(mesh, options, &range);

  const SurfaceQuery query(mesh);
  const Framing framing = frame(mesh, options, view_width);
  const Camera& camera = framing.camera;
  const Eigen::Vector3d& center = framing.center;
  const double pixel = framing.pixel;
  const double distance_back = framing.distance_back;
  const Eigen::Vector3d key_light = (-camera.direction + 0.6 * camera.up - 0.3 * camera.right).normalized();
  std::vector<Eigen::Vector3d> face_normals(mesh.triangles.size());
  for (std::size_t t = 0; t < face_normals.size(); ++t) face_normals[t] = morph::face_normal(mesh, t);
  const bool use_colors = !scalar && mesh.colors.size() == mesh.vertices.size();

  tbb::parallel_for(0, image.height, [&](int y) {
    for (int x = 0; x < view_width; ++x) {
      const double sx = (x + 0.5 - 0.5 * view_width) * pixel;
      const double sy = (0.5 * image.height - (y + 0.5)) * pixel;
      const Eigen::Vector3d origin =
          center + sx * camera.right + sy * camera.up - distance_back * camera.direction;
      const RayHit hit = query.first_hit(origin, camera.direction);
      if (!hit.hit) continue;
      const morph::Triangle& tri = mesh.triangles[hit.triangle];
      const double w[3] = {1 - hit.u - hit.v, hit.u, hit.v};
      // Flat shading: machined parts have sharp edges that interpolated normals would blur.
      const Eigen::Vector3d& n = face_normals[hit.triangle];
      // Ambient, headlight and a key light from above-left, so faces at equal angles to the view
      // (a box seen in iso view) still differ; two-sided so open meshes and inverted faces show.
      const double light =
          options.lighting ? 0.2 + 0.5 * std::abs(n.dot(camera.direction)) + 0.3 * std::abs(n.dot(key_light))
                           : 1.0;
      std::array<double, 3> base{200, 200, 200};
      if (scalar) {
        const double value =
            w[0] * scalar->values[tri[0]] + w[1] * scalar->values[tri[1]] + w[2] * scalar->values[tri[2]];
        const morph::Color c = map_value(options.color_map, range, value);
        base = {double(c[0]), double(c[1]), double(c[2])};
      } else if (use_colors) {
        for (int k = 0; k < 3; ++k)
          base[k] =
              w[0] * mesh.colors[tri[0]][k] + w[1] * mesh.colors[tri[1]][k] + w[2] * mesh.colors[tri[2]][k];
      }
      const std::size_t i = 3 * (static_cast<std::size_t>(y) * image.width + x);
      for (int k = 0; k < 3; ++k)
        image.rgb[i + k] = static_cast<std::uint8_t>(std::lround(std::clamp(base[k] * light, 0.0, 255.0)));
    }
  });

  if (scalar || !options.caption.empty()) {
    detail::Legend legend;
    if (scalar) legend = legend_of(*scalar, options, range);
    legend.panel_x = view_width;
    detail::draw_legend(image, legend, options.caption);
  }
  return image;
}

Eigen::Vector2d project_to_pixel(const morph::TriangleMesh& mesh, const RenderOptions& options,
                                 const Eigen::Vector3d& point) {
  const Framing f = frame(mesh, options, view_width_of(mesh, options, nullptr));
  const Eigen::Vector3d d = point - f.center;
  return {0.5 * f.view_width + d.dot(f.camera.right) / f.pixel - 0.5,
          0.5 * options.height - d.dot(f.camera.up) / f.pixel - 0.5};
}

void write_png(const Image& image, const std::string& path) {
  if (image.width <= 0 || image.height <= 0 ||
      image.rgb.size() != static_cast<std::size_t>(image.width) * image.height * 3)
    throw morph::IoError("write_png: " + path + ": the image is empty or inconsistent");
  // Encoded in memory, then written whole (temporary file and rename): a kill mid-write never
  // leaves a truncated picture where a good one was.
  std::string bytes;
  const auto append = [](void* context, void* data, int size) {
    static_cast<std::string*>(context)->append(static_cast<const char*>(data),
                                               static_cast<std::size_t>(size));
  };
  if (!stbi_write_png_to_func(append, &bytes, image.width, image.height, 3, image.rgb.data(),
                              image.width * 3))
    throw morph::IoError("cannot encode PNG file " + path);
  morph::write_file_atomically(path, bytes);
}

}  // namespace raytest
