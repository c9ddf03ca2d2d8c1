// SPDX-License-Identifier: Apache-2.0
#include "generator/double_double_filter.h"

#include <cfloat>
#include <cmath>

namespace morph::exact {
namespace {

constexpr double kUnit = DBL_EPSILON / 2;           // u = 2^-53
constexpr double kMinorBound = 32 * kUnit * kUnit;  // k = 4 (file comment of the header)
constexpr double kDet4Bound = 64 * kUnit * kUnit;   // k = 8
constexpr double kUnderflowSlack = 0x1p-1000;       // absolute, for gradual underflow
constexpr double kSmallestPermanent = 0x1p-900;

// A double word: the unevaluated sum hi + lo, |lo| <= ulp(hi)/2.
struct Word {
  double hi = 0.0, lo = 0.0;
};

Word two_sum(double a, double b) {
  const double s = a + b, bb = s - a;
  return {s, (a - (s - bb)) + (b - bb)};
}
Word fast_two_sum(double a, double b) {  // requires exponent(a) >= exponent(b) (or a == 0)
  const double s = a + b;
  return {s, b - (s - a)};
}
Word two_prod(double a, double b) {
  const double p = a * b;
  return {p, std::fma(a, b, -p)};
}
// Joldes–Muller–Popescu Algorithm 6 (AccurateDWPlusDW): relative error < 3u²/(1-4u).
Word add(const Word& x, const Word& y) {
  const Word s = two_sum(x.hi, y.hi), t = two_sum(x.lo, y.lo);
  const double c = s.lo + t.hi;
  const Word v = fast_two_sum(s.hi, c);
  const double w = t.lo + v.lo;
  return fast_two_sum(v.hi, w);
}
Word negated(const Word& x) {
  return {-x.hi, -x.lo};
}
// Algorithm 9 (DWTimesFP3): relative error <= 2u².
Word times(const Word& x, double y) {
  const Word c = two_prod(x.hi, y);
  const double cl3 = std::fma(x.lo, y, c.lo);
  return fast_two_sum(c.hi, cl3);
}

struct Value {
  Word word;
  double permanent;  // the same expression with absolute values, rounded to doubles
};

// det of the normals of a, b, c by cofactors of a's row.
Value minor(const Row& a, const Row& b, const Row& c) {
  auto two_by_two = [](double p, double q, double r, double s) {  // p·q - r·s
    return add(two_prod(p, q), negated(two_prod(r, s)));
  };
  const Word m0 = two_by_two(b[1], c[2], b[2], c[1]);
  const Word m1 = two_by_two(b[0], c[2], b[2], c[0]);
  const Word m2 = two_by_two(b[0], c[1], b[1], c[0]);
  const Word sum = add(add(times(m0, a[0]), negated(times(m1, a[1]))), times(m2, a[2]));
  const double p0 = std::fabs(b[1] * c[2]) + std::fabs(b[2] * c[1]);
  const double p1 = std::fabs(b[0] * c[2]) + std::fabs(b[2] * c[0]);
  const double p2 = std::fabs(b[0] * c[1]) + std::fabs(b[1] * c[0]);
  return {sum, std::fabs(a[0]) * p0 + std::fabs(a[1]) * p1 + std::fabs(a[2]) * p2};
}

int decided(const Word& value, double permanent, double relative_bound) {
  if (!std::isfinite(value.hi) || !std::isfinite(permanent) || permanent < kSmallestPermanent) return 0;
  // The exact value is within `bound` of hi + lo, and |lo| <= u·|hi|: twice the bound (rounded
  // up by far more than the rounding of these two operations) decides hi's sign.
  const double bound = relative_bound * permanent + kUnderflowSlack;
  if (std::fabs(value.hi) <= 2 * bound) return 0;
  return value.hi > 0 ? 1 : -1;
}

}  // namespace

int double_double_minor_sign(const Row& a, const Row& b, const Row& c) {
  const Value m = minor(a, b, c);
  return decided(m.word, m.permanent, kMinorBound);
}

int double_double_det4_sign(const std::array<Row, 4>& rows) {
  // Σ (-1)^(i+3)·offset_i·minor_i, as exact_determinant.cpp expands it.
  Word det;
  double permanent = 0.0;
  static constexpr int kOthers[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
  for (int i = 0; i < 4; ++i) {
    const Value m = minor(rows[kOthers[i][0]], rows[kOthers[i][1]], rows[kOthers[i][2]]);
    const Word term = times(m.word, rows[i][3]);
    det = add(det, i % 2 == 0 ? negated(term) : term);
    permanent += std::fabs(rows[i][3]) * m.permanent;
  }
  return decided(det, permanent, kDet4Bound);
}

}  // namespace morph::exact
