// SPDX-License-Identifier: Apache-2.0
#pragma once
// The exact signed distance to the volume a tool sweeps along one straight segment, with the
// segment's constants computed once. Every other tool shape takes the general 1-D convex search
// of morph::swept_signed_distance, skipped where the sweep of the tool's bounding ball is
// already beyond the caller's ceiling. Same value as
// morph::swept_signed_distance(tool, a, b, p) (to the rounding of its 1-D search), but the
// ball-end body's search runs only where a lower bound says the body could beat the tip's capsule,
// and then a closed-form candidate is tried first. The reference evaluates this hundreds of
// millions of times per job, so it is written for speed.
#include <morph/tool.h>

#include <Eigen/Core>

namespace vdb_ref::detail {

class StraightSweep {
 public:
  /// `tool` must outlive this (the job owns it); a and b are tool points in job units.
  StraightSweep(const morph::Tool& tool, const Eigen::Vector3d& a, const Eigen::Vector3d& b);

  /// Signed distance from p to the swept volume, job units, negative inside. 1-Lipschitz in p
  /// (the volume is convex).
  double distance(const Eigen::Vector3d& p) const;

  /// The distance where it lies strictly between `floor` and `ceiling`; elsewhere a value on the
  /// same side (<= floor, or >= ceiling), found with less work. For callers that clamp the result
  /// or only keep it if it beats a minimum so far.
  double distance_within(const Eigen::Vector3d& p, double floor, double ceiling) const;

  const Eigen::Vector3d& start() const { return a_; }
  const Eigen::Vector3d& end() const { return b_; }

 private:
  double body_distance(const Eigen::Vector3d& p) const;

  const morph::Tool* general_ = nullptr;  // set for the shapes without a closed form here
  double bounding_radius_ = 0.0;          // general: radius of a ball about centre_ holding the tool
  bool ball_end_ = false;
  double radius_ = 0.0;
  double length_ = 0.0;
  Eigen::Vector3d a_, b_;
  Eigen::Vector3d d_;       // b - a
  double dd_ = 0.0;         // |d|^2
  Eigen::Vector3d centre_;  // sphere: a; ball end: a + radius * z (the tip ball's centre);
                            // general: the middle of the tool's axis at a
  double lowest_centre_z_ = 0.0;
  double body_top_z_ = 0.0;  // highest point of the body sweep
  double hh_ = 0.0;          // |horizontal part of d|^2
};

}  // namespace vdb_ref::detail
