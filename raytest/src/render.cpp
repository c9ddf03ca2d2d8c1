// SPDX-License-Identifier: Apache-2.0
#include <morph/exceptions.h>
#include <morph/file_io.h>
#include <raytest/render.h>
#include <raytest/surface_query.h>
#include <stb/stb_easy_font.h>
#include <stb/stb_image_write.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

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

// stb_easy_font lays text out as axis-aligned quads, 16 bytes per vertex (x, y, z float + rgba).
void draw_text(Image& image, int x, int y, int scale, const std::string& text, const morph::Color& color) {
  std::vector<char> buffer(text.size() * 400 + 400);
  std::string copy = text;
  const int quads =
      stb_easy_font_print(0, 0, copy.data(), nullptr, buffer.data(), static_cast<int>(buffer.size()));
  for (int q = 0; q < quads; ++q) {
    float min_x = 1e9f, min_y = 1e9f, max_x = -1e9f, max_y = -1e9f;
    for (int k = 0; k < 4; ++k) {
      const float* vertex = reinterpret_cast<const float*>(buffer.data() + (4 * q + k) * 16);
      min_x = std::min(min_x, vertex[0]);
      max_x = std::max(max_x, vertex[0]);
      min_y = std::min(min_y, vertex[1]);
      max_y = std::max(max_y, vertex[1]);
    }
    fill_rect(image, x + static_cast<int>(min_x * scale), y + static_cast<int>(min_y * scale),
              x + static_cast<int>(max_x * scale), y + static_cast<int>(max_y * scale), color);
  }
}

int text_width(const std::string& text, int scale) {
  std::string copy = text;
  return stb_easy_font_width(copy.data()) * scale;
}

// Enough significant digits that neighbouring ticks `step` apart print differently.
std::string format_number(double v, double step) {
  const double magnitude = std::abs(v);
  int digits = 3;
  if (step > 0 && magnitude > step)
    digits = std::clamp(static_cast<int>(std::ceil(std::log10(magnitude / step))) + 2, 3, 12);
  char buffer[48];
  std::snprintf(buffer, sizeof buffer, "%.*g", digits, magnitude < 1e-12 * std::max(step, 1e-300) ? 0.0 : v);
  return buffer;
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
  std::vector<std::string> labels;
  std::string title;
  const int scale = std::clamp(std::min(image.width, image.height) / 300 + 1, 1, 4);
  int bar_panel = 0;
  if (scalar) {
    range = options.range ? *options.range : auto_range(scalar->values, options.symmetric);
    int widest = 0;
    for (int tick = 0; tick <= 4; ++tick) {
      labels.push_back(
          format_number(range.low + (range.high - range.low) * tick / 4.0, (range.high - range.low) / 4.0));
      widest = std::max(widest, text_width(labels.back(), scale));
    }
    title = scalar->name + (options.unit.empty() ? "" : " [" + options.unit + "]");
    // Gap, bar, tick, label, margin; at least as wide as the title.
    bar_panel = std::max(6 * scale + 10 * scale + 5 * scale + widest + 12 * scale,
                         text_width(title, scale) + 8 * scale);
    bar_panel = std::min(bar_panel, image.width / 2);
  }
  const int view_width = image.width - bar_panel;

  const SurfaceQuery query(mesh);
  const Camera camera = camera_for(options.view);
  const Eigen::AlignedBox3d box = morph::bounds(mesh);
  const Eigen::Vector3d center = box.center();
  double half_x = 0, half_y = 0;
  for (int corner = 0; corner < 8; ++corner) {
    const Eigen::Vector3d d = box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(corner)) - center;
    half_x = std::max(half_x, std::abs(d.dot(camera.right)));
    half_y = std::max(half_y, std::abs(d.dot(camera.up)));
  }
  // Orthographic camera fitting the projected bounds with a 6% margin.
  const double pixel = 1.12 * std::max(2 * half_x / view_width, 2 * half_y / image.height);
  const double distance_back = 2.0 * (box.diagonal().norm() + 1.0);
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
      const double light = 0.2 + 0.5 * std::abs(n.dot(camera.direction)) + 0.3 * std::abs(n.dot(key_light));
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

  if (scalar) {
    // Colour bar: high values at the top, five labelled ticks, the scalar's name as title.
    const morph::Color ink{0, 0, 0};
    const int bar_x = view_width + 6 * scale;
    const int bar_w = 10 * scale;
    const int top = image.height / 10 + 10 * scale;
    const int bottom = image.height - image.height / 10;
    for (int y = top; y < bottom; ++y) {
      const double t = 1.0 - static_cast<double>(y - top) / std::max(1, bottom - top - 1);
      fill_rect(image, bar_x, y, bar_x + bar_w, y + 1, map_color(options.color_map, t));
    }
    fill_rect(image, bar_x - 1, top - 1, bar_x + bar_w + 1, top, ink);
    fill_rect(image, bar_x - 1, bottom, bar_x + bar_w + 1, bottom + 1, ink);
    fill_rect(image, bar_x - 1, top, bar_x, bottom, ink);
    fill_rect(image, bar_x + bar_w, top, bar_x + bar_w + 1, bottom, ink);
    for (int tick = 0; tick <= 4; ++tick) {
      const int y = bottom - (bottom - top) * tick / 4;
      fill_rect(image, bar_x + bar_w, y, bar_x + bar_w + 3 * scale, y + 1, ink);
      draw_text(image, bar_x + bar_w + 5 * scale, y - 3 * scale, scale, labels[tick], ink);
    }
    const int title_x =
        std::max(view_width, std::min(bar_x, image.width - text_width(title, scale) - 4 * scale));
    draw_text(image, title_x, top - 12 * scale, scale, title, ink);
  }
  return image;
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
