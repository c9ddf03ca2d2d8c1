// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file sweep_plane_cache.h
/// One thread's memory of the planes of the sweeps it used last. The carving asks for a sweep's
/// planes (sweep_planes() of SweepPolytopeBuilder::halfspaces(), ~1000 exact planes) for every
/// stock piece the sweep may cut and for every move the sweep is a cutter of; neighbouring moves
/// and the parts of one stock piece ask for the same sweeps again. The planes are a function of
/// the sweep alone, so the held ones are the recomputed ones bit for bit.
#include <morph/plane_predicates.h>

#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

namespace morph {

class SweepPlaneCache {
 public:
  /// `capacity`: sweeps held (a sweep's planes are ~100 kB for a 1000-facet tool).
  explicit SweepPlaneCache(std::size_t capacity = 128) : capacity_(capacity) {}

  /// The planes of sweep `sweep`, from `make()` when not held. The reference is valid until the
  /// next call.
  template <class Make>
  const std::vector<ExactPlane>& get(std::uint32_t sweep, Make&& make) {
    const auto found = slot_of_.find(sweep);
    if (found != slot_of_.end()) return recent_[found->second].second;
    std::size_t slot = recent_.size();
    if (slot < capacity_) {
      recent_.emplace_back(sweep, make());
    } else {  // the oldest goes
      slot = next_;
      next_ = (next_ + 1) % capacity_;
      slot_of_.erase(recent_[slot].first);
      recent_[slot] = {sweep, make()};
    }
    slot_of_[sweep] = slot;
    return recent_[slot].second;
  }

 private:
  std::size_t capacity_;
  std::unordered_map<std::uint32_t, std::size_t> slot_of_;
  std::vector<std::pair<std::uint32_t, std::vector<ExactPlane>>> recent_;
  std::size_t next_ = 0;
};

}  // namespace morph
