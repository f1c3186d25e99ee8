#include "mgelastic/grid/transfer.hpp"

#include <algorithm>
#include <array>
#include <initializer_list>

namespace mgelastic::grid {
namespace {

struct Tap {
  int coordinate;  // stored coordinate on the other level
  double weight;
};
// Up to three taps per axis, kept on the stack (these run for every variable of every level).
struct Taps {
  std::array<Tap, 3> tap{};
  int count = 0;
  Taps() = default;
  Taps(std::initializer_list<Tap> list) {
    for (const Tap& t : list) tap[count++] = t;
  }
  const Tap* begin() const { return tap.data(); }
  const Tap* end() const { return tap.data() + count; }
  std::size_t size() const { return static_cast<std::size_t>(count); }
  const Tap& operator[](std::size_t i) const { return tap[i]; }
};

// Fine stored coordinates read by the coarse variable at coarse stored coordinate `s` along an
// axis where the variable is face-centered (B2) or cell-centered (B1).
Taps restriction_taps(int s, bool face_centered) {
  const int c = s - 1;
  if (face_centered) return {{2 * c, 0.25}, {2 * c + 1, 0.5}, {2 * c + 2, 0.25}};
  return {{2 * c + 1, 0.5}, {2 * c + 2, 0.5}};
}

// Coarse stored coordinates feeding the fine variable at fine stored coordinate `s`:
// linear interpolation (from B2 or B3) or injection for pressures.
Taps prolongation_taps(int s, bool face_centered, bool pressure) {
  const int c = s - 1;
  if (pressure) return {{c / 2 + 1, 1.0}};
  if (face_centered) {
    if (c % 2 == 0) return {{c / 2 + 1, 1.0}};
    return {{(c - 1) / 2 + 1, 0.5}, {(c + 1) / 2 + 1, 0.5}};
  }
  const int m = c / 2;
  return {{m + 1, 0.75}, {(c % 2 == 0 ? m - 1 : m + 1) + 1, 0.25}};
}

// Visits the tensor product of per-axis taps: f(stored coordinates, weight).
template <int Dim, typename F>
void for_each_tap(const std::array<Taps, Dim>& taps, F&& f) {
  IVec<Dim> s;
  auto recurse = [&](auto&& self, int a, double w) -> void {
    if (a == Dim) {
      f(s, w);
      return;
    }
    for (const Tap& t : taps[a]) {
      s[a] = t.coordinate;
      self(self, a + 1, w * t.weight);
    }
  };
  recurse(recurse, 0, 1.0);
}

template <int Dim>
bool in_storage(const Lattice<Dim>& lattice, const IVec<Dim>& s) {
  for (int a = 0; a < Dim; ++a)
    if (s[a] < 0 || s[a] > lattice.cells[a] + 1) return false;
  return true;
}

}  // namespace

template <int Dim, typename Scalar>
void restrict_residual(const Level<Dim, Scalar>& fine, Level<Dim, Scalar>& coarse) {
  const auto n = static_cast<std::ptrdiff_t>(coarse.size());
  for (int field = 0; field <= Dim; ++field) {
    std::fill(coarse.x[field].begin(), coarse.x[field].end(), Scalar(0));
    std::fill(coarse.b[field].begin(), coarse.b[field].end(), Scalar(0));
    const std::vector<Scalar>& r = fine.r[field];
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t k = 0; k < n; ++k) {
      if (coarse.kind[field][k] != VarKind::INTERIOR) continue;
      const IVec<Dim> s = coarse.lattice.coords(k);
      std::array<Taps, Dim> taps;
      for (int a = 0; a < Dim; ++a) taps[a] = restriction_taps(s[a], a == field);
      double sum = 0.0;
      for_each_tap<Dim>(taps, [&](const IVec<Dim>& fs, double w) {
        if (in_storage(fine.lattice, fs)) sum += w * r[fine.lattice.index(fs)];
      });
      coarse.b[field][k] = static_cast<Scalar>(sum);
    }
  }
}

namespace {

// A coarse value seen by the prolongation, with what kind of variable it came from.
struct Sample {
  enum State { INACTIVE, DIRICHLET, ACTIVE } state = INACTIVE;
  double value = 0.0;
};

// Linear interpolation along one axis. Along a cell-centered axis a Dirichlet coarse variable
// lies inside the Dirichlet region, half a coarse cell past the wall where the correction
// vanishes, so it is replaced by the odd reflection of its partner (value 0 on the wall).
Sample combine(const Sample& main, double w_main, const Sample& other, double w_other,
               bool cell_centered) {
  if (other.state == Sample::INACTIVE) return main;
  if (main.state == Sample::INACTIVE) return other;
  if (cell_centered && other.state == Sample::DIRICHLET && main.state == Sample::ACTIVE)
    return {Sample::ACTIVE, (w_main - w_other) * main.value};
  const auto state = std::max(main.state, other.state);
  return {cell_centered ? main.state : state, w_main * main.value + w_other * other.value};
}

template <int Dim, typename Scalar>
Sample coarse_sample(const Level<Dim, Scalar>& coarse, int field, const IVec<Dim>& s) {
  const std::ptrdiff_t k = coarse.lattice.index(s);
  switch (coarse.kind[field][k]) {
    case VarKind::INACTIVE:
      return {};

    case VarKind::DIRICHLET:
      return {Sample::DIRICHLET, static_cast<double>(coarse.x[field][k])};
    default:
      return {Sample::ACTIVE, static_cast<double>(coarse.x[field][k])};
  }
}

// Tensor-product interpolation, one axis at a time from the last to the first.
template <int Dim, typename Scalar>
Sample interpolate(const Level<Dim, Scalar>& coarse, int field, const std::array<Taps, Dim>& taps,
                   IVec<Dim>& s, int axis) {
  if (axis < 0) return coarse_sample(coarse, field, s);
  const Taps& t = taps[axis];
  s[axis] = t[0].coordinate;
  const Sample first = interpolate<Dim, Scalar>(coarse, field, taps, s, axis - 1);
  if (t.size() == 1) return first;
  s[axis] = t[1].coordinate;
  const Sample second = interpolate<Dim, Scalar>(coarse, field, taps, s, axis - 1);
  return combine(first, t[0].weight, second, t[1].weight, axis != field);
}

}  // namespace

template <int Dim, typename Scalar>
void prolongate_correction(const Level<Dim, Scalar>& coarse, Level<Dim, Scalar>& fine) {
  const auto n = static_cast<std::ptrdiff_t>(fine.size());
  for (int field = 0; field < Dim; ++field) {
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t k = 0; k < n; ++k) {
      if (fine.kind[field][k] != VarKind::INTERIOR) continue;
      const IVec<Dim> s = fine.lattice.coords(k);
      std::array<Taps, Dim> taps;
      for (int a = 0; a < Dim; ++a) taps[a] = prolongation_taps(s[a], a == field, false);
      IVec<Dim> cs;
      const Sample sample = interpolate<Dim, Scalar>(coarse, field, taps, cs, Dim - 1);
      if (sample.state != Sample::INACTIVE) fine.x[field][k] += static_cast<Scalar>(sample.value);
    }
  }
  // Pressures: piecewise constant injection from interior coarse cells.
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t k = 0; k < n; ++k) {
    if (fine.kind[Dim][k] != VarKind::INTERIOR) continue;
    IVec<Dim> cs = fine.lattice.coords(k);
    for (int a = 0; a < Dim; ++a) cs[a] = (cs[a] - 1) / 2 + 1;
    const std::ptrdiff_t ck = coarse.lattice.index(cs);
    if (coarse.kind[Dim][ck] == VarKind::INTERIOR) fine.x[Dim][k] += coarse.x[Dim][ck];
  }
}

#define MGELASTIC_INSTANTIATE(D, S)                                        \
  template void restrict_residual<D, S>(const Level<D, S>&, Level<D, S>&); \
  template void prolongate_correction<D, S>(const Level<D, S>&, Level<D, S>&);
MGELASTIC_INSTANTIATE(2, float)
MGELASTIC_INSTANTIATE(2, double)
MGELASTIC_INSTANTIATE(3, float)
MGELASTIC_INSTANTIATE(3, double)
#undef MGELASTIC_INSTANTIATE

}  // namespace mgelastic::grid
