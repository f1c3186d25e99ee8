#include "mgelastic/grid/local_correction.hpp"

#include <algorithm>

#include "mgelastic/grid/boundary_smoother.hpp"

namespace mgelastic::grid {
namespace {

template <int Dim>
bool inside(const IVec<Dim>& s, const IVec<Dim>& lo, const IVec<Dim>& hi) {
  for (int a = 0; a < Dim; ++a)
    if (s[a] < lo[a] || s[a] >= hi[a]) return false;
  return true;
}

}  // namespace

template <int Dim, typename Scalar>
LocalCorrection<Dim, Scalar>::LocalCorrection(const Level<Dim, Scalar>& level,
                                              const Material& material, double inertia,
                                              IVec<Dim> lo, IVec<Dim> hi) {
  const Lattice<Dim>& fine = level.lattice;
  for (int a = 0; a < Dim; ++a) {
    lo[a] = std::max(lo[a], 1);
    hi[a] = std::max(lo[a], std::min(hi[a], fine.cells[a] + 1));
  }
  m_lo = lo;
  m_hi = hi;
  // Box cell t (1 .. m, storage coordinates of the box's lattice) is the level's cell
  // lo - 2 + t: the box's inner cells t = 2 .. m - 1 are [lo, hi), t = 1 and m the margin.
  const IVec<Dim> shift = lo - IVec<Dim>::Constant(2);
  const IVec<Dim> m = hi - lo + IVec<Dim>::Constant(2);
  const Lattice<Dim> box(m, fine.h, fine.origin + fine.h * shift.template cast<double>());
  std::vector<CellType> cells(box.size(), CellType::EXTERIOR);
  for_each_coordinate<Dim>(IVec<Dim>::Ones(), m + IVec<Dim>::Ones(), [&](const IVec<Dim>& t) {
    const CellType type = level.cells[fine.index(shift + t)];
    bool margin = false;
    for (int a = 0; a < Dim; ++a) margin = margin || t[a] == 1 || t[a] == m[a];
    cells[box.index(t)] = margin && type != CellType::EXTERIOR ? CellType::DIRICHLET : type;
  });
  m_box = build_level<Dim, double>(box, std::move(cells), material, BoundaryStress<Dim>{}, nullptr,
                                   inertia, 0, {}, 0.0, {}, false, LevelUse::RESIDUAL);
  m_solver = std::make_unique<CoarseSolver<Dim, double>>(m_box);

  IVec<Dim> row_hi = m;
  row_hi[0] = 3;  // one stretch per inner lattice row: t[0] = 2 only
  for_each_coordinate<Dim>(IVec<Dim>::Constant(2), row_hi, [&](const IVec<Dim>& t) {
    m_stretches.push_back({fine.index(shift + t), static_cast<std::uint32_t>(m[0] - 2)});
    m_box_first.push_back(box.index(t));
  });
  m_points = m_stretches.size() * static_cast<std::size_t>(m[0] - 2);
  const auto box_index = [&](std::ptrdiff_t k) { return box.index(fine.coords(k) - shift); };
  const BandKernel<Scalar>& kernel = level.band_kernel;
  for (std::uint32_t row = 0; row < kernel.rows(); ++row)
    if (inside<Dim>(fine.coords(kernel.target[row]), lo, hi)) {
      m_band_rows.push_back(row);
      m_band_target.push_back(box_index(kernel.target[row]));
    }
  for (std::uint32_t row = 0; row < level.band_p.rows(); ++row)
    if (inside<Dim>(fine.coords(level.band_p.target_index[row]), lo, hi)) {
      m_pressure_rows.push_back(row);
      m_pressure_target.push_back(box_index(level.band_p.target_index[row]));
    }
}

template <int Dim, typename Scalar>
void LocalCorrection<Dim, Scalar>::add(Level<Dim, Scalar>& level) {
  // r_R: the stencil rows of the inner cells, then the band rows over their targets.
  m_scratch.resize((Dim + 1) * m_points + std::max(m_band_rows.size(), m_pressure_rows.size()));
  std::array<double*, Dim + 1> r;
  for (int f = 0; f <= Dim; ++f) r[f] = m_scratch.data() + f * m_points;
  stencil_residual_at(level, m_stretches, r);
  const std::size_t length = m_stretches.empty() ? 0 : m_stretches.front().length;
  for (std::size_t i = 0; i < m_stretches.size(); ++i)
    for (int f = 0; f <= Dim; ++f)
      std::copy_n(r[f] + i * length, length, m_box.b[f].begin() + m_box_first[i]);
  double* rows = m_scratch.data() + (Dim + 1) * m_points;
  band_residual_at(level, m_band_rows, rows);
  const BandKernel<Scalar>& kernel = level.band_kernel;
  for (std::size_t i = 0; i < m_band_rows.size(); ++i)
    m_box.b[kernel.field[m_band_rows[i]]][m_band_target[i]] = rows[i];
  band_pressure_residual_at(level, m_pressure_rows, rows);
  for (std::size_t i = 0; i < m_pressure_rows.size(); ++i)
    m_box.b[Dim][m_pressure_target[i]] = rows[i];

  m_solver->solve(m_box);
  for (std::size_t i = 0; i < m_stretches.size(); ++i) {
    const std::ptrdiff_t kf = m_stretches[i].first, kb = m_box_first[i];
    for (int f = 0; f <= Dim; ++f)
      for (std::size_t x = 0; x < length; ++x)
        if (m_box.kind(f, kb + x) == VarKind::INTERIOR)
          level.x[f][kf + x] += static_cast<Scalar>(m_box.x[f][kb + x]);
  }
}

template <int Dim, typename Scalar>
void LocalCorrection<Dim, Scalar>::apply(Level<Dim, Scalar>& level) {
  add(level);
  back_substitute_traction(level);
}

template <int Dim, typename Scalar>
std::size_t LocalCorrection<Dim, Scalar>::bytes() const {
  return m_box.bytes() + m_solver->factor_bytes() + sizeof(Stretch) * m_stretches.capacity() +
         sizeof(std::ptrdiff_t) *
             (m_box_first.capacity() + m_band_target.capacity() + m_pressure_target.capacity()) +
         sizeof(std::uint32_t) * (m_band_rows.capacity() + m_pressure_rows.capacity()) +
         sizeof(double) * m_scratch.capacity();
}

template <int Dim, typename Scalar>
std::size_t LocalCorrection<Dim, Scalar>::apply_bytes() const {
  return 2 * m_solver->factor_bytes() + 3 * (Dim + 1) * sizeof(double) * m_box.size();
}

template <int Dim>
std::vector<std::array<IVec<Dim>, 2>> slow_mode_boxes(const std::vector<ResidualBlock<Dim>>& cubes,
                                                      int cube, const Lattice<Dim>& lattice,
                                                      double min_share, double cover, int margin) {
  std::vector<std::array<int, Dim>> chosen;
  double covered = 0;
  for (const ResidualBlock<Dim>& c : cubes) {
    if (c.share < min_share || covered >= cover) break;
    chosen.push_back(c.first);
    covered += c.share;
  }
  std::vector<std::array<IVec<Dim>, 2>> boxes;
  const IVec<Dim> lowest = IVec<Dim>::Ones();
  const IVec<Dim> highest = lattice.cells + IVec<Dim>::Ones();
  for (const auto& first : chosen) {
    IVec<Dim> lo, hi;
    for (int a = 0; a < Dim; ++a) {
      lo[a] = first[a] - margin;
      hi[a] = first[a] + cube + margin;
    }
    boxes.push_back({lo.cwiseMax(lowest), hi.cwiseMin(highest)});
  }
  const auto overlap = [](const auto& a, const auto& b) {
    for (int d = 0; d < Dim; ++d)
      if (a[1][d] <= b[0][d] || b[1][d] <= a[0][d]) return false;
    return true;
  };
  for (bool merged = true; merged;) {
    merged = false;
    for (std::size_t i = 0; i < boxes.size() && !merged; ++i)
      for (std::size_t j = i + 1; j < boxes.size() && !merged; ++j)
        if (overlap(boxes[i], boxes[j])) {
          boxes[i] = {boxes[i][0].cwiseMin(boxes[j][0]), boxes[i][1].cwiseMax(boxes[j][1])};
          boxes.erase(boxes.begin() + static_cast<std::ptrdiff_t>(j));
          merged = true;
        }
  }
  return boxes;
}

template class LocalCorrection<2, float>;
template class LocalCorrection<2, double>;
template class LocalCorrection<3, float>;
template class LocalCorrection<3, double>;
template std::vector<std::array<IVec<2>, 2>> slow_mode_boxes<2>(
    const std::vector<ResidualBlock<2>>&, int, const Lattice<2>&, double, double, int);
template std::vector<std::array<IVec<3>, 2>> slow_mode_boxes<3>(
    const std::vector<ResidualBlock<3>>&, int, const Lattice<3>&, double, double, int);

}  // namespace mgelastic::grid
