// SPDX-License-Identifier: Apache-2.0
#include "generator2/exact_determinant.h"

// GCC 12 sees a maybe-uninitialized limb inside cpp_int's own zero constant; not ours to fix.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <boost/multiprecision/cpp_int.hpp>
#pragma GCC diagnostic pop

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <stdexcept>

namespace morph::exact {
namespace {

using Int128 = __int128;
using boost::multiprecision::cpp_int;
using boost::multiprecision::int256_t;
using boost::multiprecision::int512_t;

// Bits of magnitude of each tier (the file comment of exact_determinant.h).
constexpr int kBits128 = 127, kBits256 = 256, kBits512 = 512;

// mantissa · 2^shift. The magnitude is shifted: shifting a negative value left is undefined
// before C++20 (UBSan reports it for __int128). |mantissa| < 2^53, so its negation is safe.
template <class Int>
Int shifted(std::int64_t mantissa, int shift) {
  const Int magnitude = Int(mantissa < 0 ? -mantissa : mantissa) << shift;
  return mantissa < 0 ? Int(-magnitude) : magnitude;
}

template <class Int>
int sign_of(const Int& v) {
  return (v > 0) - (v < 0);
}

template <class Int>
Int det3(const std::array<Int, 3>& a, const std::array<Int, 3>& b, const std::array<Int, 3>& c) {
  return a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
         a[2] * (b[0] * c[1] - b[1] * c[0]);
}

Width narrowest(int bits) {
  if (bits <= kBits128) return Width::Bits128;
  if (bits <= kBits256) return Width::Bits256;
  if (bits <= kBits512) return Width::Bits512;
  return Width::Unbounded;
}

int capacity(Width width) {
  switch (width) {
    case Width::Bits128:
      return kBits128;
    case Width::Bits256:
      return kBits256;
    case Width::Bits512:
      return kBits512;
    default:
      return INT32_MAX;
  }
}

Width checked(Width asked, int needed) {
  if (asked == Width::Auto) return narrowest(needed);
  if (needed > capacity(asked))
    throw std::logic_error("exact determinant: the integer type is too narrow for these rows");
  return asked;
}

}  // namespace

ExactRows::ExactRows(const std::array<Row, 4>& rows, int count, const std::array<double, 4>& offset_low)
    : count_(count) {
  for (int r = 0; r < count; ++r) {
    std::array<int, 5> exponent{};
    int lowest = INT32_MAX;
    for (int c = 0; c < 5; ++c) {
      const double v = c < 4 ? rows[r][c] : offset_low[r];
      if (v == 0) continue;
      int e = 0;
      const double fraction = std::frexp(v, &e);  // v = fraction·2^e, 0.5 <= |fraction| < 1
      std::int64_t m = static_cast<std::int64_t>(std::ldexp(fraction, DBL_MANT_DIG));
      e -= DBL_MANT_DIG;
      const int zeros = __builtin_ctzll(static_cast<unsigned long long>(m < 0 ? -m : m));
      mantissa_[r][c] = m / (std::int64_t{1} << zeros);
      exponent[c] = e + zeros;
      lowest = std::min(lowest, exponent[c]);
    }
    for (int c = 0; c < 5; ++c) {
      if (mantissa_[r][c] == 0) continue;
      shift_[r][c] = exponent[c] - lowest;
      const auto magnitude = static_cast<unsigned long long>(std::llabs(mantissa_[r][c]));
      const int bits = 64 - __builtin_clzll(magnitude);
      width_[r] = std::max(width_[r], bits + shift_[r][c]);
    }
    if (mantissa_[r][4] != 0) ++width_[r];  // the offset's two parts sum below 2^(W+1)
  }
}

template <class Int>
int ExactRows::det4_sign_in() const {
  std::array<std::array<Int, 3>, 4> normal;
  std::array<Int, 4> offset;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 3; ++c) normal[r][c] = shifted<Int>(mantissa_[r][c], shift_[r][c]);
    offset[r] = shifted<Int>(mantissa_[r][3], shift_[r][3]) + shifted<Int>(mantissa_[r][4], shift_[r][4]);
  }
  // Expansion along the offset column: Σ (-1)^(r+3)·offset_r·minor_r.
  Int det =
      offset[1] * det3(normal[0], normal[2], normal[3]) + offset[3] * det3(normal[0], normal[1], normal[2]);
  det -= offset[0] * det3(normal[1], normal[2], normal[3]);
  det -= offset[2] * det3(normal[0], normal[1], normal[3]);
  return sign_of(det);
}

template <class Int>
int ExactRows::minor_sign_in(int a, int b, int c) const {
  auto normal = [&](int r) {
    std::array<Int, 3> n;
    for (int k = 0; k < 3; ++k) n[k] = shifted<Int>(mantissa_[r][k], shift_[r][k]);
    return n;
  };
  return sign_of(det3(normal(a), normal(b), normal(c)));
}

int ExactRows::det4_sign(Width width) const {
  if (count_ != 4) throw std::logic_error("exact determinant: det4 of three rows");
  const int needed = width_[0] + width_[1] + width_[2] + width_[3] + 5;
  switch (checked(width, needed)) {
    case Width::Bits128:
      return det4_sign_in<Int128>();
    case Width::Bits256:
      return det4_sign_in<int256_t>();
    case Width::Bits512:
      return det4_sign_in<int512_t>();
    default:
      return det4_sign_in<cpp_int>();
  }
}

int ExactRows::minor_sign(int a, int b, int c, Width width) const {
  const int needed = width_[a] + width_[b] + width_[c] + 3;
  switch (checked(width, needed)) {
    case Width::Bits128:
      return minor_sign_in<Int128>(a, b, c);
    case Width::Bits256:
      return minor_sign_in<int256_t>(a, b, c);
    case Width::Bits512:
      return minor_sign_in<int512_t>(a, b, c);
    default:
      return minor_sign_in<cpp_int>(a, b, c);
  }
}

}  // namespace morph::exact
