#pragma once
// The uniform background lattice of the grid engine (Zhu et al. 2010, Sec. 3 and 5.1).
//
// Data layout shared by every grid field: a padded box of (n_d + 2) points per axis, x fastest,
// so that cell (c_0, ..., c_{d-1}) of the n-cell box is stored at s = c + 1 and a ghost ring of
// exterior cells surrounds the domain. With that single flat index k:
//   cell k            center  origin + (s - 1/2) h
//   face  (axis i) k  the face normal to e_i on the LOWER side of cell k, between cells k - s_i, k
//   edge  (i, j) k    the edge (3D) / node (2D) at the lower corner of cell k along e_i and e_j
//   u_i lives on faces of axis i, the pressure p at cell centers (Fig. 1 and 3 of the paper).
#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <cstdint>

namespace mgelastic::grid {

template <int Dim>
using IVec = Eigen::Matrix<int, Dim, 1>;
template <int Dim>
using Vec = Eigen::Matrix<double, Dim, 1>;

// Cell partition of Sec. 5.1: Dirichlet overrides interior/exterior.
enum class CellType : std::uint8_t { EXTERIOR = 0, INTERIOR = 1, DIRICHLET = 2 };

template <int Dim>
struct Lattice {
  IVec<Dim> cells;                     // n_d cells along each axis
  double h = 1.0;                      // cubic cell size
  Vec<Dim> origin = Vec<Dim>::Zero();  // world position of the min corner of cell (0, ..., 0)

  Lattice() = default;
  Lattice(const IVec<Dim>& n, double cell_size, const Vec<Dim>& min_corner = Vec<Dim>::Zero())
      : cells(n), h(cell_size), origin(min_corner) {
    std::ptrdiff_t s = 1;
    for (int a = 0; a < Dim; ++a) {
      m_stride[a] = s;
      s *= n[a] + 2;
    }
    m_size = static_cast<std::size_t>(s);
  }

  std::size_t size() const { return m_size; }  // number of padded storage points
  std::ptrdiff_t stride(int axis) const { return m_stride[axis]; }
  int padded(int axis) const { return cells[axis] + 2; }

  // Flat index of stored coordinates s (0 .. n+1 per axis).
  std::ptrdiff_t index(const IVec<Dim>& s) const {
    std::ptrdiff_t k = 0;
    for (int a = 0; a < Dim; ++a) k += s[a] * m_stride[a];
    return k;
  }
  IVec<Dim> coords(std::ptrdiff_t k) const {
    IVec<Dim> s;
    for (int a = Dim - 1; a >= 0; --a) {
      s[a] = static_cast<int>(k / m_stride[a]);
      k -= s[a] * m_stride[a];
    }
    return s;
  }
  // True for stored coordinates of a real (non-ghost) cell.
  bool is_real(const IVec<Dim>& s) const {
    for (int a = 0; a < Dim; ++a)
      if (s[a] < 1 || s[a] > cells[a]) return false;
    return true;
  }

  Vec<Dim> cell_center(std::ptrdiff_t k) const {
    return origin + h * (coords(k).template cast<double>() - Vec<Dim>::Constant(0.5));
  }
  Vec<Dim> face_center(int axis, std::ptrdiff_t k) const {
    Vec<Dim> x = cell_center(k);
    x[axis] -= 0.5 * h;
    return x;
  }
  Vec<Dim> edge_center(int axis_i, int axis_j, std::ptrdiff_t k) const {
    Vec<Dim> x = cell_center(k);
    x[axis_i] -= 0.5 * h;
    x[axis_j] -= 0.5 * h;
    return x;
  }

 private:
  std::array<std::ptrdiff_t, Dim> m_stride{};
  std::size_t m_size = 0;
};

// Calls visit(s) for every s with lo <= s < hi (componentwise), x fastest; none if the box is
// empty.
template <int Dim, typename Visit>
void for_each_coordinate(const IVec<Dim>& lo, const IVec<Dim>& hi, Visit&& visit) {
  for (int a = 0; a < Dim; ++a)
    if (lo[a] >= hi[a]) return;
  IVec<Dim> s = lo;
  while (true) {
    visit(s);
    int a = 0;
    while (a < Dim && ++s[a] == hi[a]) {
      s[a] = lo[a];
      ++a;
    }
    if (a == Dim) return;
  }
}

}  // namespace mgelastic::grid
