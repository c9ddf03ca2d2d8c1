// SPDX-License-Identifier: Apache-2.0
#include "generator/exact_determinant.h"

// GCC 12 sees a maybe-uninitialized limb inside cpp_int's own zero constant; not ours to fix.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <boost/multiprecision/cpp_int.hpp>
#pragma GCC diagnostic pop

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <stdexcept>
#include <type_traits>

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

std::array<double, 3> ExactRows::meeting_point() const {
  std::array<std::array<cpp_int, 3>, 3> normal;
  std::array<cpp_int, 3> offset;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) normal[r][c] = shifted<cpp_int>(mantissa_[r][c], shift_[r][c]);
    offset[r] =
        shifted<cpp_int>(mantissa_[r][3], shift_[r][3]) + shifted<cpp_int>(mantissa_[r][4], shift_[r][4]);
  }
  const cpp_int denominator = det3(normal[0], normal[1], normal[2]);
  if (denominator == 0)
    throw std::invalid_argument("meeting_point: the three planes have no single common point");
  const cpp_int divisor = abs(denominator);
  std::array<double, 3> x{};
  for (int col = 0; col < 3; ++col) {
    std::array<std::array<cpp_int, 3>, 3> m = normal;
    for (int r = 0; r < 3; ++r) m[r][col] = offset[r];
    const cpp_int numerator = det3(m[0], m[1], m[2]);
    if (numerator == 0) continue;
    // A quotient of at least 64 bits, then scaled back: the double is within an ulp of it.
    const cpp_int magnitude = abs(numerator);
    const long shift =
        std::max<long>(0, 64 + static_cast<long>(msb(divisor)) - static_cast<long>(msb(magnitude)));
    const cpp_int quotient = (magnitude << shift) / divisor;
    const double value = std::ldexp(quotient.convert_to<double>(), -static_cast<int>(shift));
    x[col] = (numerator < 0) != (denominator < 0) ? -value : value;
  }
  return x;
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

namespace morph::exact {
namespace {

int bit_length(__int128 v) {
  const auto u = static_cast<unsigned __int128>(v < 0 ? -v : v);
  const auto high = static_cast<std::uint64_t>(u >> 64), low = static_cast<std::uint64_t>(u);
  if (high != 0) return 128 - __builtin_clzll(high);
  return low != 0 ? 64 - __builtin_clzll(low) : 0;
}

int normal_bits(const IntegerPlane& p) {
  int bits = 0;
  for (std::int64_t n : p.normal) bits = std::max(bits, bit_length(n));
  return bits;
}

template <class Int>
Int from_int128(__int128 v) {
  if constexpr (std::is_same_v<Int, Int128>) {
    return v;
  } else {
    const auto magnitude = static_cast<unsigned __int128>(v < 0 ? -v : v);
    Int value = Int(static_cast<std::uint64_t>(magnitude >> 64));
    value <<= 64;
    value += Int(static_cast<std::uint64_t>(magnitude));
    return v < 0 ? Int(-value) : value;
  }
}

template <class Int>
std::array<Int, 3> normal_of(const IntegerPlane& p) {
  return {Int(p.normal[0]), Int(p.normal[1]), Int(p.normal[2])};
}

// A 256-bit two's complement integer in four 64-bit limbs, least significant first: sums and
// products modulo 2^256, so a value known to lie below 2^255 in magnitude comes out exact
// whatever the intermediate sums did. About five times faster than Boost's signed-magnitude
// int256 on the determinants below (no normalisation, products of only the limbs that count).
struct Wide {
  std::array<std::uint64_t, 4> limb{};

  static Wide from(unsigned __int128 magnitude, bool negative) {
    Wide w;
    w.limb[0] = static_cast<std::uint64_t>(magnitude);
    w.limb[1] = static_cast<std::uint64_t>(magnitude >> 64);
    return negative ? w.negated() : w;
  }
  Wide negated() const {
    Wide w;
    unsigned __int128 carry = 1;
    for (int i = 0; i < 4; ++i) {
      carry += static_cast<std::uint64_t>(~limb[i]);
      w.limb[i] = static_cast<std::uint64_t>(carry);
      carry >>= 64;
    }
    return w;
  }
  Wide& operator+=(const Wide& other) {
    unsigned __int128 carry = 0;
    for (int i = 0; i < 4; ++i) {
      carry += static_cast<unsigned __int128>(limb[i]) + other.limb[i];
      limb[i] = static_cast<std::uint64_t>(carry);
      carry >>= 64;
    }
    return *this;
  }
  bool negative() const { return (limb[3] >> 63) != 0; }
  int sign() const {
    if (negative()) return -1;
    return (limb[0] | limb[1] | limb[2] | limb[3]) != 0 ? 1 : 0;
  }
  // The magnitude of a value below 2^255 in magnitude.
  Wide magnitude() const { return negative() ? negated() : *this; }
};

// x·y modulo 2^256 for a magnitude x below 2^128 and a magnitude y (Wide, non-negative).
Wide times(unsigned __int128 x, const Wide& y) {
  const std::array<std::uint64_t, 2> a{static_cast<std::uint64_t>(x), static_cast<std::uint64_t>(x >> 64)};
  Wide out;
  for (int i = 0; i < 2; ++i) {
    if (a[i] == 0) continue;
    unsigned __int128 carry = 0;
    for (int j = 0; i + j < 4; ++j) {
      carry += static_cast<unsigned __int128>(a[i]) * y.limb[j] + out.limb[i + j];
      out.limb[i + j] = static_cast<std::uint64_t>(carry);
      carry >>= 64;
    }
  }
  return out;
}

unsigned __int128 magnitude_of(__int128 v) {
  return v < 0 ? static_cast<unsigned __int128>(-(v + 1)) + 1 : static_cast<unsigned __int128>(v);
}

// det[normals of a, b, c] as a Wide: the 2×2 minors in __int128 (normals ≤ 2^52, so each minor
// is below 2^106), each times a normal component below 2^53: at most 2^161, far inside.
Wide wide_det3(const IntegerPlane& a, const IntegerPlane& b, const IntegerPlane& c) {
  using I = __int128;
  const std::array<I, 3> minor{I(b.normal[1]) * c.normal[2] - I(b.normal[2]) * c.normal[1],
                               I(b.normal[2]) * c.normal[0] - I(b.normal[0]) * c.normal[2],
                               I(b.normal[0]) * c.normal[1] - I(b.normal[1]) * c.normal[0]};
  Wide det;
  for (int k = 0; k < 3; ++k) {
    const std::int64_t n = a.normal[k];
    if (n == 0 || minor[k] == 0) continue;
    const Wide product = times(magnitude_of(minor[k]), Wide::from(magnitude_of(n), false));
    det += (n < 0) != (minor[k] < 0) ? product.negated() : product;
  }
  return det;
}

// Sign of det[n_i | offset_i] when every partial value is below 2^255 (the caller's bound).
int wide_det4_sign(const std::array<const IntegerPlane*, 4>& p) {
  // Expansion along the offset column: Σ (-1)^(r+3)·offset_r·minor_r.
  const std::array<std::array<int, 3>, 4> others{{{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}}};
  Wide det;
  for (int r = 0; r < 4; ++r) {
    const __int128 offset = p[r]->offset;
    if (offset == 0) continue;
    const Wide minor = wide_det3(*p[others[r][0]], *p[others[r][1]], *p[others[r][2]]);
    const int s = minor.sign();
    if (s == 0) continue;
    const Wide product = times(magnitude_of(offset), minor.magnitude());
    const bool negative = ((offset < 0) != (s < 0)) != (r % 2 == 0);  // (-1)^(r+3)
    det += negative ? product.negated() : product;
  }
  return det.sign();
}

template <class Int>
int integer_det4_in(const std::array<const IntegerPlane*, 4>& p) {
  std::array<std::array<Int, 3>, 4> n;
  for (int r = 0; r < 4; ++r) n[r] = normal_of<Int>(*p[r]);
  Int det = from_int128<Int>(p[1]->offset) * det3(n[0], n[2], n[3]) +
            from_int128<Int>(p[3]->offset) * det3(n[0], n[1], n[2]);
  det -= from_int128<Int>(p[0]->offset) * det3(n[1], n[2], n[3]);
  det -= from_int128<Int>(p[2]->offset) * det3(n[0], n[1], n[3]);
  return sign_of(det);
}

}  // namespace

int integer_det4_sign(const std::array<const IntegerPlane*, 4>& planes, Width width) {
  // Term by term: offset_i times the minor of the other three rows' normals (each product of
  // three normal components below 2^(their widths' sum)); 24 terms in all.
  std::array<int, 4> normal{};
  for (int r = 0; r < 4; ++r) normal[r] = normal_bits(*planes[r]);
  const int normals = normal[0] + normal[1] + normal[2] + normal[3];
  int needed = 0;
  for (int r = 0; r < 4; ++r)
    needed = std::max(needed, bit_length(planes[r]->offset) + normals - normal[r] + 5);
  switch (checked(width, needed)) {
    case Width::Bits128:
      return integer_det4_in<Int128>(planes);
    case Width::Bits256:
      return needed < kBits256 ? wide_det4_sign(planes) : integer_det4_in<int256_t>(planes);
    case Width::Bits512:
      return integer_det4_in<int512_t>(planes);
    default:
      return integer_det4_in<cpp_int>(planes);
  }
}

int integer_minor_sign(const IntegerPlane& a, const IntegerPlane& b, const IntegerPlane& c, Width width) {
  const int normal = std::max({normal_bits(a), normal_bits(b), normal_bits(c)});
  switch (checked(width, 3 * normal + 3)) {
    case Width::Bits128:
      return sign_of(det3(normal_of<Int128>(a), normal_of<Int128>(b), normal_of<Int128>(c)));
    case Width::Bits256:
      return wide_det3(a, b, c).sign();  // 3·52 + 3 bits at most: far below 2^255
    default:
      return sign_of(det3(normal_of<int512_t>(a), normal_of<int512_t>(b), normal_of<int512_t>(c)));
  }
}

}  // namespace morph::exact
