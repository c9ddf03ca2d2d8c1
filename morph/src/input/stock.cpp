// SPDX-License-Identifier: Apache-2.0
#include <morph/exceptions.h>
#include <morph/stock.h>

#include <cmath>
#include <stdexcept>

namespace morph {

const char* to_string(StockType type) {
  switch (type) {
    case StockType::Box:
      return "box";
    case StockType::Cylinder:
      return "cylinder";
    case StockType::Mesh:
      return "mesh";
  }
  return "unknown";
}

Eigen::AlignedBox3d bounds(const Stock& stock) {
  switch (stock.type) {
    case StockType::Box:
      return stock.box;
    case StockType::Cylinder: {
      Eigen::AlignedBox3d box;
      // A disc of radius r normal to unit a spans r*sqrt(1 - a_i^2) along axis i.
      const Eigen::Vector3d a = stock.axis;
      const Eigen::Vector3d half =
          stock.radius * (Eigen::Vector3d::Ones() - a.cwiseAbs2()).cwiseMax(0.0).cwiseSqrt();
      for (const Eigen::Vector3d& c : {stock.base, Eigen::Vector3d(stock.base + stock.height * a)}) {
        box.extend(c - half);
        box.extend(c + half);
      }
      return box;
    }
    case StockType::Mesh:
      return bounds(stock.mesh);
  }
  return {};
}

double volume(const Stock& stock) {
  switch (stock.type) {
    case StockType::Box:
      return stock.box.volume();
    case StockType::Cylinder:
      return M_PI * stock.radius * stock.radius * stock.height;
    case StockType::Mesh:
      return enclosed_volume(stock.mesh);
  }
  return 0.0;
}

double surface_area(const Stock& stock) {
  switch (stock.type) {
    case StockType::Box: {
      const Eigen::Vector3d s = stock.box.sizes();
      return 2.0 * (s.x() * s.y() + s.y() * s.z() + s.z() * s.x());
    }
    case StockType::Cylinder:
      return 2.0 * M_PI * stock.radius * (stock.radius + stock.height);
    case StockType::Mesh:
      return surface_area(stock.mesh);
  }
  return 0.0;
}

double analytic_signed_distance(const Stock& stock, const Eigen::Vector3d& p) {
  switch (stock.type) {
    case StockType::Box: {
      const Eigen::Vector3d d = (stock.box.min() - p).cwiseMax(p - stock.box.max());
      return d.cwiseMax(0.0).norm() + std::min(d.maxCoeff(), 0.0);
    }
    case StockType::Cylinder: {
      const Eigen::Vector3d q = p - stock.base;
      const double h = q.dot(stock.axis);
      const double dr = (q - h * stock.axis).norm() - stock.radius;
      const double dz = std::max(-h, h - stock.height);
      return std::hypot(std::max(dr, 0.0), std::max(dz, 0.0)) + std::min(std::max(dr, dz), 0.0);
    }
    case StockType::Mesh:
      break;
  }
  throw std::logic_error("analytic_signed_distance: mesh stock has no closed form; use MeshDistance");
}

}  // namespace morph
