#include "mgelastic/grid/transfer.hpp"

#include <algorithm>
#include <array>
#include <initializer_list>
#include <type_traits>

#include "mgelastic/core/threads.hpp"

namespace mgelastic::grid {
namespace {

// Whether a storage row of n variables holds an INTERIOR one. Both transfers write only
// INTERIOR variables, so rows without one (outside an embedded body, most of its bounding box)
// are skipped without reading the other level.
bool has_interior(FieldKinds kind, int n) {
  return kind.any(n, VarKind::INTERIOR);
}

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

// Calls row(s) for every storage row along axis 0 (s[0] = 0), rows split among threads in
// interleaved blocks (threads.hpp: an embedded body's rows with work are not spread evenly).
template <int Dim, typename F>
void for_each_row(const Lattice<Dim>& lattice, F&& row) {
  std::ptrdiff_t rows = 1;
  for (int a = 1; a < Dim; ++a) rows *= lattice.padded(a);
  const std::ptrdiff_t block = interleaved_block(rows);
#pragma omp parallel for schedule(static, block)
  for (std::ptrdiff_t r = 0; r < rows; ++r) {
    IVec<Dim> s;
    s[0] = 0;
    std::ptrdiff_t q = r;
    for (int a = 1; a < Dim; ++a) {
      s[a] = static_cast<int>(q % lattice.padded(a));
      q /= lattice.padded(a);
    }
    row(s);
  }
}

// Adds the tensor product of fine taps in the order of the reference formula (axis 0
// outermost, weights multiplied in axis order); taps outside the fine storage were dropped.
template <int Dim, typename Scalar>
void restrict_taps(const Lattice<Dim>& fine, const Scalar* r, const std::array<Taps, Dim>& taps,
                   int axis, std::ptrdiff_t offset, double weight, double& sum) {
  if (axis == Dim) {
    sum += weight * static_cast<double>(r[offset]);
    return;
  }
  for (const Tap& t : taps[axis])
    restrict_taps<Dim, Scalar>(fine, r, taps, axis + 1, offset + t.coordinate * fine.stride(axis),
                               weight * t.weight, sum);
}

Taps stored_restriction_taps(int s, bool face_centered, int padded) {
  Taps all = restriction_taps(s, face_centered), kept;
  for (const Tap& t : all)
    if (t.coordinate >= 0 && t.coordinate < padded) kept.tap[kept.count++] = t;
  return kept;
}

}  // namespace

namespace {

// Coarse rows of restriction sums along x: for one coarse storage row (fixed s[1..Dim-1]) the
// fine rows it reads (the outer taps, axis 1 outermost as restrict_taps visits them) with
// their weight products, and the x taps' count T0 (3 along the field's own axis, else 2).
template <int Dim>
struct OuterRestrictionTaps {
  static constexpr int max_rows = Dim == 3 ? 6 : 3;
  std::array<std::ptrdiff_t, max_rows> offset{};
  std::array<double, max_rows> weight{};
  int count = 0;
};

// Fast path of restrict_residual over the coarse x range where every x tap lies in the fine
// storage (2 (i - 1) >= 0 and 2 i < fine padded): every sum evaluated (no branch, so GCC
// vectorizes it), then stored at the coarse interior equations only. The sums add the same
// products (powers of two times r, exact weights) in the same order as restrict_taps: x taps
// outermost, then the outer rows in visiting order, so the result is bit-identical.
template <int T0, int Rows, typename Scalar>
void restrict_row_range(const Scalar* r, const std::ptrdiff_t* offset, const double* weight,
                        FieldKinds kind, Scalar* b, int first, int last) {
  constexpr double w0[3] = {T0 == 3 ? 0.25 : 0.5, T0 == 3 ? 0.5 : 0.5, 0.25};
  constexpr int shift = T0 == 3 ? -2 : -1;  // first fine x tap: 2 (i - 1) + 1 - (T0 == 3)
  std::array<const Scalar*, Rows> row;
  std::array<double, Rows * T0> w;
  for (int o = 0; o < Rows; ++o) row[o] = r + offset[o] + shift;
  for (int t = 0; t < T0; ++t)
    for (int o = 0; o < Rows; ++o) w[t * Rows + o] = w0[t] * weight[o];
  constexpr int chunk = 64;
  for (int begin = first; begin <= last; begin += chunk) {
    const int m = std::min(chunk, last - begin + 1);
    double sum[chunk];
    for (int j = 0; j < m; ++j) {
      const int fi = 2 * (begin + j);
      double acc = 0.0;
      for (int t = 0; t < T0; ++t)
        for (int o = 0; o < Rows; ++o) acc += w[t * Rows + o] * static_cast<double>(row[o][fi + t]);
      sum[j] = acc;
    }
    for (int j = 0; j < m; ++j)
      if (kind[begin + j] == VarKind::INTERIOR) b[begin + j] = static_cast<Scalar>(sum[j]);
  }
}

template <int T0, typename Scalar, int Dim>
void restrict_row_dispatch(const Scalar* r, const OuterRestrictionTaps<Dim>& outer, FieldKinds kind,
                           Scalar* b, int first, int last) {
  const auto* o = outer.offset.data();
  const auto* w = outer.weight.data();
  switch (outer.count) {
    case 1:
      return restrict_row_range<T0, 1>(r, o, w, kind, b, first, last);
    case 2:
      return restrict_row_range<T0, 2>(r, o, w, kind, b, first, last);
    case 3:
      return restrict_row_range<T0, 3>(r, o, w, kind, b, first, last);
    case 4:
      return restrict_row_range<T0, 4>(r, o, w, kind, b, first, last);
    case 6:
      return restrict_row_range<T0, 6>(r, o, w, kind, b, first, last);
    default: {
      // Clipped outer taps (rows at the storage edge): not reached by interior equations on
      // the lattices coarsen() makes, kept general.
      for (int i = first; i <= last; ++i) {
        if (kind[i] != VarKind::INTERIOR) continue;
        double acc = 0.0;
        for (int t = 0; t < T0; ++t)
          for (int q = 0; q < outer.count; ++q)
            acc += (std::array<double, 3>{T0 == 3 ? 0.25 : 0.5, 0.5, 0.25}[t] * w[q]) *
                   static_cast<double>(r[o[q] + 2 * i + t + (T0 == 3 ? -2 : -1)]);
        b[i] = static_cast<Scalar>(acc);
      }
    }
  }
}

}  // namespace

namespace {

// The restriction of one field into one coarse storage row s (s[0] = 0): r is the fine
// residual of that field (indexable at the fine flat indices the row's taps read).
template <int Dim, typename Scalar>
void restrict_coarse_row(const Level<Dim, Scalar>& fine, const Scalar* r,
                         Level<Dim, Scalar>& coarse, int field, const IVec<Dim>& s) {
  // Coarse x coordinates whose taps all lie in the fine storage (fast path).
  const int first = 1;
  const int last = std::min(coarse.lattice.padded(0) - 1, (fine.lattice.padded(0) - 1) / 2);
  std::array<Taps, Dim> taps;
  for (int a = 1; a < Dim; ++a)
    taps[a] = stored_restriction_taps(s[a], a == field, fine.lattice.padded(a));
  const std::ptrdiff_t base = coarse.lattice.index(s);
  FieldKinds kind = coarse.codes.kinds(field) + base;
  if (!has_interior(kind, coarse.lattice.padded(0))) return;  // b stays zero
  Scalar* b = coarse.b[field].data() + base;
  auto general = [&](int i) {
    if (kind[i] != VarKind::INTERIOR) return;
    taps[0] = stored_restriction_taps(i, field == 0, fine.lattice.padded(0));
    double sum = 0.0;
    restrict_taps<Dim, Scalar>(fine.lattice, r, taps, 0, 0, 1.0, sum);
    b[i] = static_cast<Scalar>(sum);
  };
  for (int i = 0; i < std::min(first, coarse.lattice.padded(0)); ++i) general(i);
  for (int i = std::max(last + 1, first); i < coarse.lattice.padded(0); ++i) general(i);
  if (last < first) return;
  // Outer fine rows in restrict_taps' order: axis 1 outermost, the last axis innermost.
  OuterRestrictionTaps<Dim> outer;
  outer.count = 1;
  outer.weight[0] = 1.0;
  for (int a = Dim - 1; a >= 1; --a) {
    OuterRestrictionTaps<Dim> next;
    for (const Tap& t : taps[a])
      for (int q = 0; q < outer.count; ++q) {
        next.offset[next.count] = t.coordinate * fine.lattice.stride(a) + outer.offset[q];
        next.weight[next.count] = t.weight * outer.weight[q];
        ++next.count;
      }
    outer = next;
  }
  if (field == 0)
    restrict_row_dispatch<3>(r, outer, kind, b, first, last);
  else
    restrict_row_dispatch<2>(r, outer, kind, b, first, last);
}

}  // namespace

template <int Dim, typename Scalar>
void restrict_residual(const Level<Dim, Scalar>& fine, Level<Dim, Scalar>& coarse) {
  for (int field = 0; field <= Dim; ++field) {
    zero_live(coarse.x[field], coarse.live);
    zero_live(coarse.b[field], coarse.live);
    const Scalar* r = fine.r[field].data();
    for_each_row<Dim>(coarse.lattice,
                      [&](const IVec<Dim>& s) { restrict_coarse_row(fine, r, coarse, field, s); });
  }
}

template <int Dim, typename Scalar>
void restrict_residual_planes(const Level<Dim, Scalar>& fine,
                              const std::array<const Scalar*, Dim + 1>& r,
                              Level<Dim, Scalar>& coarse, int first, int end) {
  IVec<Dim> s;
  s[0] = 0;
  for (int field = 0; field <= Dim; ++field)
    for (int z = first; z < end; ++z) {
      s[Dim - 1] = z;
      if constexpr (Dim == 3) {
        for (int y = 0; y < coarse.lattice.padded(1); ++y) {
          s[1] = y;
          restrict_coarse_row(fine, r[field], coarse, field, s);
        }
      } else {
        restrict_coarse_row(fine, r[field], coarse, field, s);
      }
    }
}

namespace {

// A coarse value seen by the prolongation, with what kind of variable it came from. V is the
// value: a number (the correction) or a LinearCombination of coarse variables (the explicit
// prolongation row, prolongation_row), so both follow one set of rules.
template <typename V>
struct BasicSample {
  enum State { INACTIVE, DIRICHLET, ACTIVE } state = INACTIVE;
  V value{};
};
using Sample = BasicSample<double>;

LinearCombination operator*(double w, LinearCombination c) {
  for (auto& term : c.terms) term.second *= w;
  return c;
}
LinearCombination operator+(LinearCombination a, const LinearCombination& b) {
  a.terms.insert(a.terms.end(), b.terms.begin(), b.terms.end());
  return a;
}

// Linear interpolation along one axis. Along a cell-centered axis a Dirichlet coarse variable
// lies inside the Dirichlet region, half a coarse cell past the wall, so the partner is instead
// extrapolated to zero at `depth` (in coarse cells) past the wall: the depth where the finest
// level clamps (Level::dirichlet_zero_depth; 0 = on the wall, the odd reflection).
template <typename V>
BasicSample<V> combine(const BasicSample<V>& main, double w_main, const BasicSample<V>& other,
                       double w_other, bool cell_centered, double depth) {
  using S = BasicSample<V>;
  if (other.state == S::INACTIVE) return main;
  if (main.state == S::INACTIVE) return other;
  if (cell_centered && other.state == S::DIRICHLET && main.state == S::ACTIVE)
    return {S::ACTIVE, (0.5 - w_other + depth) / (0.5 + depth) * main.value};
  const auto state = std::max(main.state, other.state);
  return {cell_centered ? main.state : state, w_main * main.value + w_other * other.value};
}

// A sample's value: for the correction the coarse x; for the explicit row the coarse variable
// itself, or nothing for a Dirichlet one (coarse corrections vanish there).
template <typename V, int Dim, typename Scalar>
V sample_value(const Level<Dim, Scalar>& coarse, int field, std::ptrdiff_t k) {
  if constexpr (std::is_same_v<V, double>) {
    return static_cast<double>(coarse.x[field][k]);
  } else {
    if (coarse.kind(field, k) == VarKind::DIRICHLET) return {};
    return {{{coarse.global(field, k), 1.0}}};
  }
}

template <typename V, int Dim, typename Scalar>
BasicSample<V> coarse_sample(const Level<Dim, Scalar>& coarse, int field, const IVec<Dim>& s) {
  using S = BasicSample<V>;
  const std::ptrdiff_t k = coarse.lattice.index(s);
  switch (coarse.kind(field, k)) {
    case VarKind::INACTIVE:
      return {};

    case VarKind::DIRICHLET:
      return {S::DIRICHLET, sample_value<V>(coarse, field, k)};
    default:
      return {S::ACTIVE, sample_value<V>(coarse, field, k)};
  }
}

// Where the zero of a clamped correction lies behind the coarse u_field variable at s (a
// Dirichlet sample beyond the interpolated point along `axis`, above it when `above`), in coarse
// cells past the coarse wall: the finest level's depth when the sample sits behind the finest
// Dirichlet wall (finest_dirichlet_wall_layers), else 0 (the wall itself).
template <int Dim, typename Scalar>
double finest_wall_depth(const Level<Dim, Scalar>& coarse, int field, const IVec<Dim>& s, int axis,
                         bool above) {
  if (coarse.dirichlet_wall_layers.empty()) return 0.0;
  const std::ptrdiff_t k = coarse.lattice.index(s);
  const int face = 2 * axis + (above ? 0 : 1);
  int layers = 1;
  for (const std::ptrdiff_t cell : {k, k - coarse.lattice.stride(field)}) {
    if (coarse.cells[cell] != CellType::DIRICHLET) return 0.0;
    const int wall = coarse.dirichlet_wall_layers[cell * 2 * Dim + face];
    if (wall == 0) return 0.0;
    layers += wall - 1;
  }
  return coarse.dirichlet_zero_depth * layers / coarse.lattice.h;
}

// Tensor-product interpolation, one axis at a time from the last to the first.
template <typename V, int Dim, typename Scalar>
BasicSample<V> interpolate(const Level<Dim, Scalar>& coarse, int field,
                           const std::array<Taps, Dim>& taps, IVec<Dim>& s, int axis) {
  if (axis < 0) return coarse_sample<V>(coarse, field, s);
  const Taps& t = taps[axis];
  s[axis] = t[0].coordinate;
  const BasicSample<V> first = interpolate<V, Dim, Scalar>(coarse, field, taps, s, axis - 1);
  if (t.size() == 1) return first;
  s[axis] = t[1].coordinate;
  const BasicSample<V> second = interpolate<V, Dim, Scalar>(coarse, field, taps, s, axis - 1);
  const double depth =
      second.state == BasicSample<V>::DIRICHLET && axis != field
          ? finest_wall_depth(coarse, field, s, axis, t[1].coordinate > t[0].coordinate)
          : 0.0;
  return combine(first, t[0].weight, second, t[1].weight, axis != field, depth);
}

// Coarse rows read by a fine storage row: the taps along axes 1..Dim-1 combined in the order
// `interpolate` visits them (last axis outermost), as row offsets and weights.
template <int Dim>
struct OuterTaps {
  static constexpr int max_rows = 1 << (Dim - 1);
  std::array<std::ptrdiff_t, max_rows> offset{};
  std::array<Taps, Dim> taps;
};

// Interpolated value over the outer axes [1, axis] from the per-row values `row` (one per outer
// tap combination, axis 1 fastest), with the weights and order of `interpolate`.
template <int Dim>
double combine_outer(const OuterTaps<Dim>& outer, const double* row, int axis, int first) {
  if (axis == 0) return row[first];
  const Taps& t = outer.taps[axis];
  const int span = 1 << (axis - 1);  // rows per tap of this axis
  const double a = combine_outer<Dim>(outer, row, axis - 1, first);
  if (t.size() == 1) return a;
  const double b = combine_outer<Dim>(outer, row, axis - 1, first + span);
  return t[0].weight * a + t[1].weight * b;
}

// Fast path of prolongate_row: the fine values at x = 2j - 1 and 2j of one storage row for
// coarse j = j0 .. j0 + m - 1, each the tensor-product interpolation of the Dim - 1 outer coarse
// rows at `offset` (axis 1 fastest; N1, N2 taps along axes 1, 2 with weights w1, w2), written
// with exactly the operations and order of prolongate_row's plain sum (same rounding):
//   x cell-centred (field != 0):  2j - 1: 0.75 x[j] + 0.25 x[j - 1],  2j: 0.75 x[j] + 0.25 x[j + 1]
//   x face-centred (field == 0):  2j - 1: x[j],                       2j: 0.5 x[j] + 0.5 x[j + 1]
// ok[q] says whether every coarse sample read is active (interior or traction); the caller
// falls back to the per-point interpolation where not. No branch inside: GCC vectorizes it.
template <int Dim, bool FaceX, int N1, int N2, typename Scalar>
void prolongate_pairs(const Scalar* cx, FieldKinds ck, const std::ptrdiff_t* offset,
                      const double* w1, const double* w2, int j0, int m, double* value,
                      std::uint8_t* ok) {
  constexpr int rows = 1 << (Dim - 1);
  // INTERIOR (1) and TRACTION (3), the active kinds, have the kind's low bit set.
  const VarCode active_bit = kind_bits(ck.field, VarKind::INTERIOR);
  auto combine = [&](const double* row) {
    const double a = N1 == 2 ? w1[0] * row[0] + w1[1] * row[1] : row[0];
    if constexpr (Dim == 2) return a;
    const double b = N1 == 2 ? w1[0] * row[2] + w1[1] * row[3] : row[2];
    return N2 == 2 ? w2[0] * a + w2[1] * b : a;
  };
  for (int q = 0; q < m; ++q) {
    const int j = j0 + q;
    double lo[rows], hi[rows];
    int active_lo = 1, active_hi = 1;
    for (int r = 0; r < rows; ++r) {
      const Scalar* row = cx + offset[r];
      const VarCode* code = ck.codes + offset[r];
      const int k_mid = (code[j] & active_bit) != 0, k_up = (code[j + 1] & active_bit) != 0;
      if constexpr (FaceX) {
        lo[r] = static_cast<double>(row[j]);
        hi[r] = 0.5 * static_cast<double>(row[j]) + 0.5 * static_cast<double>(row[j + 1]);
        active_lo &= k_mid;
      } else {
        lo[r] = 0.75 * static_cast<double>(row[j]) + 0.25 * static_cast<double>(row[j - 1]);
        hi[r] = 0.75 * static_cast<double>(row[j]) + 0.25 * static_cast<double>(row[j + 1]);
        active_lo &= k_mid & static_cast<int>((code[j - 1] & active_bit) != 0);
      }
      active_hi &= k_mid & k_up;
    }
    value[2 * q] = combine(lo);
    value[2 * q + 1] = combine(hi);
    ok[2 * q] = static_cast<std::uint8_t>(active_lo);
    ok[2 * q + 1] = static_cast<std::uint8_t>(active_hi);
  }
}

template <int Dim, typename Scalar>
void prolongate_pairs_dispatch(bool face_x, int n1, int n2, const Scalar* cx, FieldKinds ck,
                               const std::ptrdiff_t* offset, const double* w1, const double* w2,
                               int j0, int m, double* value, std::uint8_t* ok) {
  auto run = [&]<bool F, int N1, int N2>() {
    prolongate_pairs<Dim, F, N1, N2, Scalar>(cx, ck, offset, w1, w2, j0, m, value, ok);
  };
  const int key = (face_x ? 4 : 0) + (n1 == 2 ? 2 : 0) + (n2 == 2 ? 1 : 0);
  switch (key) {
    case 0:
      return run.template operator()<false, 1, 1>();
    case 1:
      return run.template operator()<false, 1, 2>();
    case 2:
      return run.template operator()<false, 2, 1>();
    case 3:
      return run.template operator()<false, 2, 2>();
    case 4:
      return run.template operator()<true, 1, 1>();
    case 5:
      return run.template operator()<true, 1, 2>();
    case 6:
      return run.template operator()<true, 2, 1>();
    default:
      return run.template operator()<true, 2, 2>();
  }
}

// Adds the interpolated correction to the interior fine u_field variables of one storage row.
// Where every coarse sample is active (interior or traction, which is the case away from
// boundaries) the plain weighted sum is used: the weights and order of `interpolate`, hence the
// same rounding, without its per-sample bookkeeping. Elsewhere `interpolate` itself.
template <int Dim, typename Scalar>
void prolongate_row(const Level<Dim, Scalar>& coarse, Level<Dim, Scalar>& fine, int field,
                    const IVec<Dim>& s) {
  const std::ptrdiff_t base = fine.lattice.index(s);
  FieldKinds fine_kind = fine.codes.kinds(field);
  if (!has_interior(fine_kind + base, fine.lattice.padded(0))) return;
  OuterTaps<Dim> outer;
  int rows = 1;
  for (int a = 1; a < Dim; ++a) {
    outer.taps[a] = prolongation_taps(s[a], a == field, false);
    rows *= 2;
  }
  // Row r combines tap bit (a - 1) of r along axis a; a missing second tap repeats the first.
  for (int r = 0; r < rows; ++r) {
    std::ptrdiff_t offset = 0;
    for (int a = 1; a < Dim; ++a) {
      const Taps& t = outer.taps[a];
      const int pick = ((r >> (a - 1)) & 1) && t.size() > 1 ? 1 : 0;
      offset += t[pick].coordinate * coarse.lattice.stride(a);
    }
    outer.offset[r] = offset;
  }
  FieldKinds coarse_kind = coarse.codes.kinds(field);
  const Scalar* cx = coarse.x[field].data();
  Scalar* x = fine.x[field].data();
  // INTERIOR (1) and TRACTION (3) are the active kinds: bit 0 set.
  auto active = [&](std::ptrdiff_t k) { return (static_cast<int>(coarse_kind[k]) & 1) != 0; };
  auto point = [&](int i) {
    if (fine_kind[base + i] != VarKind::INTERIOR) return;
    const Taps t0 = prolongation_taps(i, field == 0, false);
    std::array<double, OuterTaps<Dim>::max_rows> row{};
    bool all_active = true;
    for (int r = 0; r < rows && all_active; ++r) {
      const std::ptrdiff_t k0 = outer.offset[r] + t0[0].coordinate;
      if (t0.size() == 1) {
        all_active = active(k0);
        row[r] = static_cast<double>(cx[k0]);
      } else {
        const std::ptrdiff_t k1 = outer.offset[r] + t0[1].coordinate;
        all_active = active(k0) && active(k1);
        row[r] =
            t0[0].weight * static_cast<double>(cx[k0]) + t0[1].weight * static_cast<double>(cx[k1]);
      }
    }
    if (all_active) {
      x[base + i] += static_cast<Scalar>(combine_outer<Dim>(outer, row.data(), Dim - 1, 0));
      return;
    }
    std::array<Taps, Dim> taps = outer.taps;
    taps[0] = t0;
    IVec<Dim> cs;
    const Sample sample = interpolate<double, Dim, Scalar>(coarse, field, taps, cs, Dim - 1);
    if (sample.state != Sample::INACTIVE) x[base + i] += static_cast<Scalar>(sample.value);
  };
  // Fine x = 2j - 1 and 2j for coarse j in [1, last] in pairs (prolongate_pairs); the rest,
  // and pairs whose samples are not all active, point by point.
  // Rows at the storage edge may have outer taps outside the coarse storage: point by point.
  bool outer_in_storage = true;
  for (int a = 1; a < Dim; ++a)
    for (const Tap& t : outer.taps[a])
      outer_in_storage =
          outer_in_storage && t.coordinate >= 0 && t.coordinate < coarse.lattice.padded(a);
  // Only the row's variable span holds INTERIOR points (live_chunks.hpp).
  const auto [first, end] = row_span(fine.live, base, fine.lattice.padded(0));
  const int last =
      std::min({(fine.lattice.padded(0) - 1) / 2, coarse.lattice.padded(0) - 2, end / 2});
  const int j_first = std::max(1, (first + 1) / 2);
  int done = first;  // fine x below `done` handled
  if (last >= j_first && outer_in_storage) {
    if (first == 0) point(0);
    std::array<double, OuterTaps<Dim>::max_rows> w1{}, w2{};
    const Taps& t1 = outer.taps[1];
    w1 = {t1[0].weight, t1.size() > 1 ? t1[1].weight : 0.0};
    int n2 = 1;
    if constexpr (Dim == 3) {
      const Taps& t2 = outer.taps[2];
      w2 = {t2[0].weight, t2.size() > 1 ? t2[1].weight : 0.0};
      n2 = static_cast<int>(t2.size());
    }
    const int n1 = static_cast<int>(t1.size());
    constexpr int chunk = 64;
    alignas(64) double value[2 * chunk];
    alignas(64) std::uint8_t ok[2 * chunk];
    for (int j0 = j_first; j0 <= last; j0 += chunk) {
      const int m = std::min(chunk, last - j0 + 1);
      prolongate_pairs_dispatch<Dim, Scalar>(field == 0, n1, n2, cx, coarse_kind,
                                             outer.offset.data(), w1.data(), w2.data(), j0, m,
                                             value, ok);
      for (int q = 0; q < 2 * m; ++q) {
        const int i = 2 * j0 - 1 + q;
        if (fine_kind[base + i] != VarKind::INTERIOR) continue;
        if (ok[q])
          x[base + i] += static_cast<Scalar>(value[q]);
        else
          point(i);
      }
    }
    done = 2 * last + 1;
  }
  for (int i = done; i < end; ++i) point(i);
}

// Pressures: piecewise constant injection from interior coarse cells, one fine storage row.
template <int Dim, typename Scalar>
void prolongate_pressure_row(const Level<Dim, Scalar>& coarse, Level<Dim, Scalar>& fine,
                             const IVec<Dim>& s) {
  const FieldKinds fine_kind = fine.codes.kinds(Dim), coarse_kind = coarse.codes.kinds(Dim);
  const std::ptrdiff_t base = fine.lattice.index(s);
  const int n = fine.lattice.cells[0];
  if (!has_interior(fine_kind + base + 1, n)) return;
  IVec<Dim> cs;
  cs[0] = 0;
  for (int a = 1; a < Dim; ++a) cs[a] = (s[a] - 1) / 2 + 1;
  const std::ptrdiff_t coarse_base = coarse.lattice.index(cs);  // + cs[0] along x
  const Scalar* cp = coarse.x[Dim].data() + coarse_base;
  Scalar* p = fine.x[Dim].data() + base;
  const auto [first, end] = row_span(fine.live, base, fine.lattice.padded(0));
  for (int i = std::max(1, first); i <= std::min(n, end - 1); ++i) {
    if (fine_kind[base + i] != VarKind::INTERIOR) continue;
    const int c = (i - 1) / 2 + 1;
    if (coarse_kind[coarse_base + c] == VarKind::INTERIOR) p[i] += cp[c];
  }
}

}  // namespace

template <int Dim, typename Scalar>
void prolongate_correction(const Level<Dim, Scalar>& coarse, Level<Dim, Scalar>& fine) {
  // One pass over the fine storage rows, every field of a row in turn (its codes read from
  // memory once, not once per field); a row in dead chunks (live_chunks.hpp: no variable
  // there, most rows of an embedded body's bounding box) is skipped without reading them.
  for_each_row<Dim>(fine.lattice, [&](IVec<Dim> s) {
    const std::ptrdiff_t base = fine.lattice.index(s);
    if (!fine.live.any_live(base, base + fine.lattice.padded(0))) return;
    for (int field = 0; field < Dim; ++field) prolongate_row<Dim, Scalar>(coarse, fine, field, s);
    prolongate_pressure_row<Dim, Scalar>(coarse, fine, s);
  });
}

void merge_terms(LinearCombination& combination) {
  auto& terms = combination.terms;
  std::sort(terms.begin(), terms.end());
  std::size_t out = 0;
  for (std::size_t i = 0; i < terms.size();) {
    std::size_t j = i;
    double sum = 0.0;
    for (; j < terms.size() && terms[j].first == terms[i].first; ++j) sum += terms[j].second;
    if (sum != 0.0) terms[out++] = {terms[i].first, sum};
    i = j;
  }
  terms.resize(out);
}

template <int Dim, typename Scalar>
LinearCombination prolongation_row(const Level<Dim, Scalar>& coarse, const Level<Dim, Scalar>& fine,
                                   int field, std::ptrdiff_t k) {
  if (fine.kind(field, k) != VarKind::INTERIOR) return {};
  const IVec<Dim> s = fine.lattice.coords(k);
  std::array<Taps, Dim> taps;
  for (int a = 0; a < Dim; ++a) taps[a] = prolongation_taps(s[a], a == field, false);
  IVec<Dim> cs;
  BasicSample<LinearCombination> sample =
      interpolate<LinearCombination, Dim, Scalar>(coarse, field, taps, cs, Dim - 1);
  if (sample.state == BasicSample<LinearCombination>::INACTIVE) return {};
  merge_terms(sample.value);
  return sample.value;
}

#define MGELASTIC_INSTANTIATE(D, S)                                                              \
  template LinearCombination prolongation_row<D, S>(const Level<D, S>&, const Level<D, S>&, int, \
                                                    std::ptrdiff_t);                             \
  template void restrict_residual<D, S>(const Level<D, S>&, Level<D, S>&);                       \
  template void restrict_residual_planes<D, S>(                                                  \
      const Level<D, S>&, const std::array<const S*, D + 1>&, Level<D, S>&, int, int);           \
  template void prolongate_correction<D, S>(const Level<D, S>&, Level<D, S>&);
MGELASTIC_INSTANTIATE(2, float)
MGELASTIC_INSTANTIATE(2, double)
MGELASTIC_INSTANTIATE(3, float)
MGELASTIC_INSTANTIATE(3, double)
#undef MGELASTIC_INSTANTIATE

}  // namespace mgelastic::grid
