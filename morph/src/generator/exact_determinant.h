// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file exact_determinant.h
/// The exact stage of generator 2's plane predicates: signs of the 4×4 determinant of up to four
/// planes' rows [normal | offset] and of 3×3 minors of their normals, the doubles taken as exact
/// rationals, in the narrowest integer type that provably holds every intermediate value.
///
/// Each row is scaled by its own power of two (which keeps every sign) into integers: an entry
/// m·2^e (m odd, |m| < 2^53) becomes m·2^(e - e_low), e_low the row's lowest such exponent. A
/// row's *width* W is the largest bit length of its integers, so every entry is < 2^W.
///
/// Bound. A k×k determinant is a sum of k! products of k entries, one from each row, so every
/// term is < 2^(W_1+…+W_k) and every partial sum of the cofactor expansion evaluated below (each
/// an exact sub-sum of the expansion's terms, with their signs) is < k!·2^(ΣW) ≤ 2^(ΣW + 5) for
/// k = 4 (24 < 2^5) and 2^(ΣW + 3) for k = 3 (6 < 2^3). A signed type with B bits of magnitude
/// therefore evaluates the determinant without overflow when ΣW + 5 ≤ B (k = 4) or ΣW + 3 ≤ B
/// (k = 3). The tiers: __int128 (B = 127), Boost's fixed int256_t and int512_t (unchecked,
/// signed magnitude: B = 256, 512; no allocation), and cpp_int (unbounded, allocating) beyond.
/// An offset may come as two doubles whose sum is the exact offset (an IntegerPlane's, quantize.h):
/// both parts are scaled with the row, and the row's width is one more than its largest entry's,
/// since their sum is below 2^(W+1).
///
/// Unquantized unit normals have W ≈ 53–120 (int256/int512); quantized planes (integer normals
/// and offsets on a grid, quantize.h) have W ≤ 53 and mostly fit __int128 or int256.
#include <morph/quantize.h>

#include <array>
#include <cstdint>

namespace morph::exact {

using Row = std::array<double, 4>;  ///< normal x, y, z, offset

/// Which integer type evaluates: Auto picks the narrowest that the bound allows; the others
/// force one (for tests; a forced type the bound does not allow throws std::logic_error).
enum class Width { Auto, Bits128, Bits256, Bits512, Unbounded };

/// Up to four rows as exact integers (see the file comment).
class ExactRows {
 public:
  /// The first `count` (3 or 4) of `rows`, row r's offset being rows[r][3] + offset_low[r]
  /// exactly; entries must be finite.
  explicit ExactRows(const std::array<Row, 4>& rows, int count = 4,
                     const std::array<double, 4>& offset_low = {});

  /// Sign of det[rows 0..3] (all four columns).
  int det4_sign(Width width = Width::Auto) const;
  /// Sign of det[normals of rows a, b, c] (in that order).
  int minor_sign(int a, int b, int c, Width width = Width::Auto) const;

  /// The point where the planes of rows 0, 1, 2 meet (the planes are normal·x = offset), each
  /// coordinate the exact rational by Cramer's rule in unbounded integers, rounded to a double
  /// within an ulp. Throws std::invalid_argument when their normals are dependent.
  std::array<double, 3> meeting_point() const;

  /// The width W of row r (bits; 0 for a zero row).
  int width(int r) const { return width_[r]; }

 private:
  // Columns: normal x, y, z, offset, offset's low part.
  std::array<std::array<std::int64_t, 5>, 4> mantissa_{};  // odd or zero
  std::array<std::array<int, 5>, 4> shift_{};              // left shift of the mantissa
  std::array<int, 4> width_{};
  int count_ = 4;

  template <class Int>
  int det4_sign_in() const;
  template <class Int>
  int minor_sign_in(int a, int b, int c) const;
};

/// Sign of det[n_i | offset_i] of four planes exactly on one grid (IntegerPlane, quantize.h),
/// straight from their integers: the offset column in grid units is the doubles' column times
/// 2^-g for every row, a positive scaling that keeps the sign. Bound: with every normal component
/// below 2^Wn and every offset below 2^Wo, each of the 24 terms is below 2^(3Wn+Wo) and so is
/// every partial sum below 2^(3Wn+Wo+5); the narrowest tier with that many bits evaluates it
/// (normals ≤ 52 bits and offsets ≤ 101 bits: at most 262 bits, int512).
int integer_det4_sign(const std::array<const IntegerPlane*, 4>& planes, Width width = Width::Auto);
/// Sign of det[normals of a, b, c] of integer planes (bound 3Wn+3 bits).
int integer_minor_sign(const IntegerPlane& a, const IntegerPlane& b, const IntegerPlane& c,
                       Width width = Width::Auto);

}  // namespace morph::exact
