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
