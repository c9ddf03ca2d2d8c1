// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file sweep_plane_cache.h
/// One thread's memory of the planes of the sweeps it used last. The carving asks for a sweep's
/// planes (sweep_planes() of SweepPolytopeBuilder::halfspaces(), ~1000 exact planes) for every
/// stock piece the sweep may cut and for every move the sweep is a cutter of; neighbouring moves
/// and the parts of one stock piece ask for the same sweeps again. The planes are a function of
/// the sweep alone, so the held ones are the recomputed ones bit for bit.
#include <morph/plane_predicates.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

namespace morph {

class SweepPlaneCache {
 public:
  /// `bytes`: the planes held at most (a sweep's are ~100 kB for an 800-facet tool). The stock
  /// face of a raster is split along every pass, and its parts ask for the passes after the one
  /// that split them: a few hundred sweeps must stay held for those to be found again.
  explicit SweepPlaneCache(std::size_t bytes = std::size_t{64} << 20) : bytes_(bytes) {}

  /// How many sweeps of `planes` planes each it holds.
  std::size_t sweeps_held(std::size_t planes) const {
    return std::max<std::size_t>(16, bytes_ / (sizeof(ExactPlane) * (planes + 1)));
  }

  /// The planes of sweep `sweep`, from `make()` when not held. The reference is valid until the
  /// next call.
  template <class Make>
  const std::vector<ExactPlane>& get(std::uint32_t sweep, Make&& make) {
    const auto found = slot_of_.find(sweep);
    if (found != slot_of_.end()) return recent_[found->second].second;
    std::vector<ExactPlane> planes = make();
    // Sweeps of one tool have about the same number of planes: the first one sets the count.
    if (capacity_ == 0)
      capacity_ = std::max<std::size_t>(16, bytes_ / (sizeof(ExactPlane) * (planes.size() + 1)));
    std::size_t slot = recent_.size();
    if (slot < capacity_) {
      recent_.emplace_back(sweep, std::move(planes));
    } else {  // the oldest goes
      slot = next_;
      next_ = (next_ + 1) % capacity_;
      slot_of_.erase(recent_[slot].first);
      recent_[slot] = {sweep, std::move(planes)};
    }
    slot_of_[sweep] = slot;
    return recent_[slot].second;
  }

 private:
  std::size_t bytes_;
  std::size_t capacity_ = 0;  ///< sweeps held
  std::unordered_map<std::uint32_t, std::size_t> slot_of_;
  std::vector<std::pair<std::uint32_t, std::vector<ExactPlane>>> recent_;
  std::size_t next_ = 0;
};

}  // namespace morph
