// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file stock.h
/// The stock X: box, cylinder or closed triangle mesh.
#include <morph/mesh.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>

namespace morph {

enum class StockType { Box, Cylinder, Mesh };

const char* to_string(StockType type);

struct Stock {
  StockType type = StockType::Box;
  Eigen::AlignedBox3d box;                          ///< Box
  Eigen::Vector3d base = Eigen::Vector3d::Zero();   ///< Cylinder: centre of the bottom disc
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();  ///< Cylinder: unit axis
  double radius = 0.0;                              ///< Cylinder
  double height = 0.0;                              ///< Cylinder
  TriangleMesh mesh;                                ///< Mesh (closed, outward)
  std::string mesh_path;                            ///< Mesh: file it was read from
};

/// Axis-aligned bounds of the stock.
Eigen::AlignedBox3d bounds(const Stock& stock);
/// Exact volume (mesh: divergence theorem).
double volume(const Stock& stock);
/// Exact surface area.
double surface_area(const Stock& stock);
/// Exact signed distance for Box and Cylinder; throws std::logic_error for Mesh (use a
/// MeshDistance from morph/mesh_distance.h).
double analytic_signed_distance(const Stock& stock, const Eigen::Vector3d& p);

}  // namespace morph
