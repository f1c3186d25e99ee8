#pragma once
// Checks that make a problem well-posed before any work starts: valid material, a lattice that
// can be coarsened at least once, at least one interior cell, and every connected piece of the
// body (face-connected interior cells) held by a Dirichlet cell — traction-only pieces are
// singular in statics (rigid motions).
#include "mgelastic/grid/problem.hpp"

namespace mgelastic::grid {

template <int Dim>
void validate(const ElasticityProblem<Dim>& problem);

}  // namespace mgelastic::grid
