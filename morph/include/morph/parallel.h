// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file parallel.h
/// Sequential or parallel execution, chosen by the caller (results are identical either way).
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>

#include <cstddef>

namespace morph {

enum class ExecutionPolicy { Sequential, Parallel };

/// Calls f(i) for i in [begin, end). f must write only to slots owned by i.
template <class F>
void for_each_index(ExecutionPolicy policy, std::size_t begin, std::size_t end, F&& f) {
  if (policy == ExecutionPolicy::Sequential || end - begin < 2) {
    for (std::size_t i = begin; i < end; ++i) f(i);
    return;
  }
  tbb::parallel_for(begin, end, [&](std::size_t i) { f(i); });
}

/// Touches each page of the `bytes` at `data` (reserved, not yet written) under `policy`, so the
/// kernel maps them in parallel: a vector of hundreds of megabytes resized by one thread spent
/// most of its time faulting its pages in, serial. The bytes written are zero.
inline void fault_in_pages(void* data, std::size_t bytes, ExecutionPolicy policy) {
  constexpr std::size_t kPage = 4096, kBlock = 512 * kPage;
  auto* first = static_cast<unsigned char*>(data);
  for_each_index(policy, 0, (bytes + kBlock - 1) / kBlock, [&](std::size_t b) {
    for (std::size_t at = b * kBlock; at < std::min(bytes, (b + 1) * kBlock); at += kPage) first[at] = 0;
  });
}

/// `v` with room for `size` elements, the pages of its new room faulted in under `policy`.
template <class Vector>
void reserve_faulted_in(Vector& v, std::size_t size, ExecutionPolicy policy) {
  if (size <= v.capacity()) return;
  v.reserve(size);
  fault_in_pages(v.data() + v.size(), (size - v.size()) * sizeof(v[0]), policy);
}

/// `v` resized to `size` default elements, its new pages faulted in under `policy` first.
template <class Vector>
void resize_faulted_in(Vector& v, std::size_t size, ExecutionPolicy policy) {
  reserve_faulted_in(v, size, policy);
  v.resize(size);
}

/// Sorts [begin, end) by `less` under `policy`. Not stable: give `less` a total order where the
/// result must not depend on the policy.
template <class It, class Less>
void sort_under(ExecutionPolicy policy, It begin, It end, Less&& less) {
  if (policy == ExecutionPolicy::Sequential)
    std::sort(begin, end, less);
  else
    tbb::parallel_sort(begin, end, less);
}

}  // namespace morph
