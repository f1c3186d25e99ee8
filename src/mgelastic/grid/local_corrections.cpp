#include "mgelastic/grid/local_corrections.hpp"

#include <algorithm>
#include <map>

#include "mgelastic/core/error.hpp"
#include "mgelastic/grid/boundary_smoother.hpp"

namespace mgelastic::grid {

namespace {

// Cells of `level` in the storage coordinates [lo, hi) that are not exterior.
template <int Dim, typename Scalar>
std::size_t body_cells_in(const Level<Dim, Scalar>& level, const IVec<Dim>& lo,
                          const IVec<Dim>& hi) {
  std::size_t count = 0;
  for_each_coordinate<Dim>(lo, hi, [&](const IVec<Dim>& s) {
    count += level.cells[level.lattice.index(s)] != CellType::EXTERIOR;
  });
  return count;
}

}  // namespace

template <int Dim, typename Scalar>
LocalCorrections<Dim, Scalar>::LocalCorrections(int limit, const Material& material, double inertia)
    : m_limit(limit), m_material(material), m_inertia(inertia) {}

template <int Dim, typename Scalar>
void LocalCorrections<Dim, Scalar>::apply(Level<Dim, Scalar>& fine) {
  if (m_local.empty()) return;
  // One traction pass over the level after all boxes instead of one per box: a box next to an
  // earlier one may read that box's traction variables before they follow (a slightly weaker
  // step where boxes touch; placed boxes never overlap).
  for (auto& local : m_local) local->add(fine);
  back_substitute_traction(fine);
}

template <int Dim, typename Scalar>
bool LocalCorrections<Dim, Scalar>::due(int cycles, double ratio, double previous) {
  m_cycles_since_placement += cycles;
  if (m_limit <= 0 || m_placement_stopped || m_cycles_since_placement < kLocalCorrectionWatch)
    return false;
  if (m_placement_on_trial) {
    m_placement_on_trial = false;
    const bool passed = ratio < kLocalCorrectionGain * m_ratio_at_placement;
    if (!passed && m_trial_failed) {
      m_local = std::move(m_local_fallback);
      m_placement_stopped = true;
      return false;
    }
    if (!passed) m_local_fallback = m_local_before;
    m_trial_failed = !passed;
  }
  const auto slow = [](double r) { return r > kLocalCorrectionRatio && r < 1.0; };
  if (!slow(ratio) || !slow(previous)) return false;
  m_cycles_since_placement = 0;
  m_ratio_at_placement = ratio;
  return true;
}

template <int Dim, typename Scalar>
int LocalCorrections<Dim, Scalar>::cube(const Level<Dim, Scalar>& fine) const {
  return std::clamp(fine.lattice.cells.maxCoeff() / kLocalCorrectionCubesPerSide, 2, 8);
}

template <int Dim, typename Scalar>
void LocalCorrections<Dim, Scalar>::place(const Level<Dim, Scalar>& fine,
                                          const std::vector<std::array<IVec<Dim>, 2>>& boxes) {
  m_local_before = m_local;
  const auto body =
      static_cast<double>(std::count_if(fine.cells.begin(), fine.cells.end(),
                                        [](CellType type) { return type != CellType::EXTERIOR; }));
  const auto cap = std::min(kLocalCorrectionMaxCells,
                            std::max(kLocalCorrectionMinCells,
                                     static_cast<std::size_t>(kLocalCorrectionBodyShare * body)));
  for (auto [lo, hi] : boxes) {
    // A box that overlaps boxes placed before replaces them by the union of all.
    std::vector<std::size_t> overlapping;
    for (std::size_t i = 0; i < m_local.size(); ++i)
      if (((lo.array() < m_local[i]->hi().array()) && (m_local[i]->lo().array() < hi.array()))
              .all())
        overlapping.push_back(i);
    bool covered = false;
    for (std::size_t i : overlapping) {
      covered = covered || ((lo.array() >= m_local[i]->lo().array()).all() &&
                            (hi.array() <= m_local[i]->hi().array()).all());
      lo = lo.cwiseMin(m_local[i]->lo());
      hi = hi.cwiseMax(m_local[i]->hi());
    }
    const bool room = static_cast<int>(m_local.size() - overlapping.size()) < m_limit;
    if (covered || !room || body_cells_in(fine, lo, hi) > cap) continue;
    try {
      auto local =
          std::make_shared<LocalCorrection<Dim, Scalar>>(fine, m_material, m_inertia, lo, hi);
      for (auto i = overlapping.rbegin(); i != overlapping.rend(); ++i)
        m_local.erase(m_local.begin() + static_cast<std::ptrdiff_t>(*i));
      m_local.push_back(std::move(local));
    } catch (const Error&) {
      // A box whose system is singular (a part of the body the margin does not hold) or empty
      // (only clamped cells): no correction there; the solve goes on without it.
    }
  }
  m_placement_on_trial = m_local != m_local_before;
}

// Layout of State::integers: cycles since the placement, on trial, trial failed,
// stopped, the sizes of m_local, m_local_before and m_local_fallback, then their boxes (lo, hi).
template <int Dim, typename Scalar>
auto LocalCorrections<Dim, Scalar>::state() const -> State {
  State state;
  state.ratio_at_placement = m_ratio_at_placement;
  auto& v = state.integers;
  v = {m_cycles_since_placement,
       m_placement_on_trial,
       m_trial_failed,
       m_placement_stopped,
       static_cast<std::int64_t>(m_local.size()),
       static_cast<std::int64_t>(m_local_before.size()),
       static_cast<std::int64_t>(m_local_fallback.size())};
  for (const auto* list : {&m_local, &m_local_before, &m_local_fallback})
    for (const auto& local : *list) {
      for (int a = 0; a < Dim; ++a) v.push_back(local->lo()[a]);
      for (int a = 0; a < Dim; ++a) v.push_back(local->hi()[a]);
    }
  return state;
}

template <int Dim, typename Scalar>
void LocalCorrections<Dim, Scalar>::restore(const Level<Dim, Scalar>& fine, const State& state) {
  const auto& v = state.integers;
  const auto bad = [] { throw Error("malformed local correction state", {.pointer = "grid"}); };
  if (v.size() < 7) bad();
  const std::size_t boxes = static_cast<std::size_t>(v[4] + v[5] + v[6]);
  if (v[4] < 0 || v[5] < 0 || v[6] < 0 || v.size() != 7 + 2 * Dim * boxes) bad();
  m_cycles_since_placement = static_cast<int>(v[0]);
  m_placement_on_trial = v[1] != 0;
  m_trial_failed = v[2] != 0;
  m_placement_stopped = v[3] != 0;
  m_ratio_at_placement = state.ratio_at_placement;
  // One correction per distinct box, shared by the lists that hold it.
  std::map<std::array<int, 2 * Dim>, std::shared_ptr<LocalCorrection<Dim, Scalar>>> built;
  std::size_t next = 7;
  const auto read = [&](std::int64_t count) {
    std::vector<std::shared_ptr<LocalCorrection<Dim, Scalar>>> list;
    for (std::int64_t i = 0; i < count; ++i, next += 2 * Dim) {
      std::array<int, 2 * Dim> key;
      for (int a = 0; a < 2 * Dim; ++a) key[a] = static_cast<int>(v[next + a]);
      auto& local = built[key];
      if (!local) {
        IVec<Dim> lo, hi;
        for (int a = 0; a < Dim; ++a) {
          lo[a] = key[a];
          hi[a] = key[Dim + a];
        }
        local = std::make_shared<LocalCorrection<Dim, Scalar>>(fine, m_material, m_inertia, lo, hi);
      }
      list.push_back(local);
    }
    return list;
  };
  m_local = read(v[4]);
  m_local_before = read(v[5]);
  m_local_fallback = read(v[6]);
}

template <int Dim, typename Scalar>
std::size_t LocalCorrections<Dim, Scalar>::bytes() const {
  std::size_t sum = 0;
  for (const auto& local : m_local) sum += local->bytes();
  return sum;
}

template class LocalCorrections<2, float>;
template class LocalCorrections<2, double>;
template class LocalCorrections<3, float>;
template class LocalCorrections<3, double>;

}  // namespace mgelastic::grid
