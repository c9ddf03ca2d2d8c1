// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file double_double_filter.h
/// The second filter of generator 2's plane predicates, between the double filter and the exact
/// integers (exact_determinant.h): the same determinants in double-word arithmetic (a value as
/// an unevaluated sum hi + lo of doubles, ~106 bits), with a proved error bound, so the many
/// near-ties that rounded planes make (values ~1e-17 of their permanent, far below the double
/// filter's ~1e-15) are decided without integers; only values within ~1e-30 of their permanent
/// (in practice the exact zeros) go on.
///
/// Building blocks (Joldes, Muller, Popescu, "Tight and rigorous error bounds for basic building
/// blocks of double-word arithmetic", ACM TOMS 44(2), 2017): the product of two doubles is exact
/// as a double word (TwoProd with FMA); the sum of two double words (their Algorithm 6) has
/// relative error below 3u²/(1-4u), a double word times a double (their Algorithm 9) below 2u²,
/// u = 2^-53. Taking δ = 4u² for every operation, a value computed through at most k operations
/// from exact doubles is within ((1+δ)^k - 1) ≤ 1.01·k·δ of the *permanent* (the same expression
/// with every input and partial sum replaced by its absolute value; Higham, Accuracy and
/// Stability, Lemma 3.1 applied node by node). The 3×3 minor by cofactors is k = 4 deep (the
/// products exact, the 2×2 difference, the product with a row entry, two sums), the 4×4
/// determinant along the offset column k = 8 (one product and three sums more). The bounds below,
/// 32u² and 64u² of the permanent, cover those (16.2u², 32.4u²) and the rounding of the permanent
/// itself in doubles (relative (1+u)^12 - 1). Underflow breaks the relative model: each operation
/// may then lose up to 2^-1074 absolutely, so an absolute 2^-1000 is added and a permanent below
/// 2^-900 is left to the integers; overflow gives a non-finite value, also left to them.
#include "generator/exact_determinant.h"

namespace morph::exact {

/// Sign of det[rows 0..3] if the double-word filter decides it, else 0.
int double_double_det4_sign(const std::array<Row, 4>& rows);
/// Sign of det[normals of a, b, c] if the double-word filter decides it, else 0.
int double_double_minor_sign(const Row& a, const Row& b, const Row& c);

}  // namespace morph::exact
