#pragma once
// Tolerances used across the test suite, each with the reason it has its size.
#include <limits>

namespace mgelastic::test {

// Relative agreement of two double-precision solves of the same well-conditioned system.
inline constexpr double kSolveAgreement = 1e-8;
// Round-off of one stencil application in double: a few ulps times the stencil width.
inline constexpr double kStencilRoundoff = 1e-11;
// Symmetry of an operator applied to random vectors, relative to |x||Ay|.
inline constexpr double kSymmetry = 1e-12;

}  // namespace mgelastic::test
