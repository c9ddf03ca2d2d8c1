// SPDX-License-Identifier: Apache-2.0
#pragma once
// Step 1 of the limit step (degenerate_collapse.h): which of the conformed surface's vertices are
// one exact point.
#include <morph/conform.h>
#include <morph/parallel.h>
#include <morph/plane_predicates.h>

#include <array>
#include <cstdint>
#include <vector>

namespace morph {

/// Each vertex's class of one exact point (same_limit_point()), as its smallest member: the same
/// whatever the order or the threads. `points`, when given, receives each vertex's
/// vertex_point(), which the classes are found by.
std::vector<std::uint32_t> limit_classes(const VertexPlanes& vertices, ExecutionPolicy policy,
                                         std::vector<Eigen::Vector3d>* points = nullptr);

}  // namespace morph
