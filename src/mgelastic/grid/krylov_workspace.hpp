#pragma once
// The storage of the accelerated solve (Multigrid::solve_accelerated, multigrid_fgmres.cpp), kept
// by the hierarchy from one solve to the next: a quasistatic run solves once per frame, and fresh
// vectors fault in their pages on every solve (tens of megabytes each at 256 cells, several
// microseconds per 4 KiB page on a virtual machine). Held until the hierarchy goes.
#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace mgelastic::grid {

// The INTERIOR variables of a level, field by field in lattice order. The Krylov vectors hold
// one value per such variable: indexed over the whole box (field * size + k) they were 8-9x
// larger on embedded bodies, and their serial passes dominated the solve (armadillo at 256
// cells: 144 s and 11.6 GB for 19 cycles against 18 s and 2.3 GB for 41 plain cycles).
template <int Dim>
struct InteriorVariables {
  std::array<std::vector<std::uint32_t>, Dim + 1> points;  // lattice points of each field
  std::array<std::ptrdiff_t, Dim + 2> offset{};            // field f at [offset[f], offset[f + 1])
  std::ptrdiff_t size() const { return offset[Dim + 1]; }
};

template <int Dim, typename Scalar>
struct KrylovWorkspace {
  using ScalarVector = Eigen::Matrix<Scalar, Eigen::Dynamic, 1>;
  // The variable codes do not change after the hierarchy's build: built by the first solve.
  InteriorVariables<Dim> vars;
  // The iterate, the true residual, the origin of the operator products (r at x_I = 0) and the
  // vector an iteration orthogonalizes, in double.
  Eigen::VectorXd x, r, r_zero, w;
  // The Krylov basis and its preconditioned vectors in the hierarchy's precision: the cycle
  // returns z exactly; a float basis vector (mixed precision) carries a relative rounding of
  // ~6e-8, which the restart's true residual in double absorbs (same cycle counts on the scenes,
  // 116 instead of 160 bytes per interior unknown with FGMRES(10)).
  std::vector<ScalarVector> v;
  std::vector<ScalarVector> z;

  std::size_t bytes() const {
    std::size_t total = 0;
    for (const auto& p : vars.points) total += p.capacity() * sizeof(std::uint32_t);
    for (const Eigen::VectorXd* d : {&x, &r, &r_zero, &w})
      total += static_cast<std::size_t>(d->size()) * sizeof(double);
    for (const auto* list : {&v, &z})
      for (const ScalarVector& s : *list)
        total += static_cast<std::size_t>(s.size()) * sizeof(Scalar);
    return total;
  }
};

}  // namespace mgelastic::grid
