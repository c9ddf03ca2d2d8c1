// SPDX-License-Identifier: Apache-2.0
#pragma once
// Private to morph: large arrays backed by 2 MiB pages where the system offers them.
//
// Why: the generator's clean-up passes each fill arrays of tens of megabytes that nothing has
// touched before, and every fresh 4 KiB page costs a page fault. Under virtualisation a fault
// costs several microseconds, so that a 60 MB array took 0.2 s to zero: more than the work done
// with it. Backed by transparent huge pages, the same array needs 512 times fewer faults.
#include <cstddef>
#include <iterator>
#include <vector>

namespace morph::detail {

/// Asks the kernel to back the whole 2 MiB-aligned pages inside [data, data + bytes) by huge
/// pages on first touch (Linux's madvise(MADV_HUGEPAGE), where transparent huge pages are
/// enabled for advised memory). Only advice: does nothing elsewhere or if refused.
void advise_huge_pages(const void* data, std::size_t bytes);

/// v.reserve(n), the new storage advised onto huge pages before anything is moved into it.
template <class T>
void reserve_large(std::vector<T>& v, std::size_t n) {
  if (n <= v.capacity()) return;
  std::vector<T> grown;
  grown.reserve(n);
  advise_huge_pages(grown.data(), grown.capacity() * sizeof(T));
  grown.insert(grown.end(), std::make_move_iterator(v.begin()), std::make_move_iterator(v.end()));
  v.swap(grown);
}

/// n copies of `value`, in storage advised as reserve_large does.
template <class T>
std::vector<T> large_vector(std::size_t n, const T& value = T()) {
  std::vector<T> v;
  reserve_large(v, n);
  v.resize(n, value);
  return v;
}

}  // namespace morph::detail
