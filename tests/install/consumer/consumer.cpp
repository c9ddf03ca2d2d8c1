// SPDX-License-Identifier: Apache-2.0
// Built against an installed MorphMill by tests/install/install_test.sh: a groove cut by a sphere
// of radius 2 through a 20 x 10 x 10 block, computed by the generator (morph) and the OpenVDB
// reference (vdb_ref), measured against each other (raytest), and checked against closed form.
#include <morph/erode.h>
#include <morph/topology.h>
#include <raytest/deviation.h>
#include <vdb_ref/reference.h>

#include <cmath>
#include <cstdio>

int main() {
  const double radius = 2.0, pi = std::acos(-1.0);
  morph::Job job;
  job.name = "groove";
  job.stock.type = morph::StockType::Box;
  job.stock.box = Eigen::AlignedBox3d(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(20, 10, 10));
  morph::Tool tool;
  tool.number = 1;
  tool.type = morph::ToolType::Sphere;
  tool.radius = radius;
  job.tools[1] = tool;
  morph::Move move;
  move.kind = morph::MoveKind::Linear;
  move.start = Eigen::Vector3d(-5, 5, 10);  // the sphere's centre runs along the top face
  move.end = Eigen::Vector3d(25, 5, 10);
  move.tool = 1;
  morph::Path path;
  path.moves.push_back(move);
  job.paths.push_back(path);

  // Half a cylinder of radius 2 and length 20 leaves the block.
  const double expected = 20.0 * 10.0 * 10.0 - 0.5 * pi * radius * radius * 20.0;

  morph::ErodeOptions erode_options;
  erode_options.tolerance = 0.005;
  const morph::ErodeResult part = morph::erode(job, erode_options);
  const morph::TopologyReport topology = morph::topology_report(part.mesh);

  vdb_ref::ReferenceOptions reference_options;
  reference_options.voxel_size = 0.25;
  const vdb_ref::ReferenceResult reference = vdb_ref::compute_reference(job, reference_options);

  raytest::DeviationOptions deviation_options;
  deviation_options.sampling.face_samples = 2000;
  const raytest::TwoSidedDeviation deviation =
      raytest::measure_two_sided(part.mesh, reference.mesh, deviation_options);

  std::printf("generator volume %.4f, reference volume %.4f, expected %.4f, hausdorff %.4f\n",
              topology.volume, reference.volume(), expected, deviation.hausdorff);
  // The generator is within its tolerance of the exact surface, flat but for the groove's half
  // cylinder (area pi * 2 * 20); the reference cuts sharp edges (the block's 160 mm, the groove
  // rims' 40 mm) by about a voxel; the two agree within tolerance + sqrt(3) * voxel (as verify).
  const double generator_bound = erode_options.tolerance * pi * radius * 20.0;
  const double reference_bound = reference_options.voxel_size * reference_options.voxel_size * 200.0;
  const double agreement_bound = erode_options.tolerance + std::sqrt(3.0) * reference_options.voxel_size;
  const bool ok = topology.closed_manifold() && std::abs(topology.volume - expected) <= generator_bound &&
                  std::abs(reference.volume() - expected) <= reference_bound &&
                  deviation.hausdorff <= agreement_bound && reference.pieces.size() == 1;
  std::puts(ok ? "consumer: ok" : "consumer: WRONG");
  return ok ? 0 : 1;
}
