#include "mgelastic/grid/residual_restriction.hpp"

#include <omp.h>

#include <algorithm>
#include <array>
#include <cstring>

#include "mgelastic/grid/residual.hpp"
#include "mgelastic/grid/transfer.hpp"

namespace mgelastic::grid {
namespace {

constexpr int kWindowPlanes = 3;      // fine planes one coarse plane reads
constexpr int kCoarsePlaneBlock = 8;  // coarse planes per work item (one window restart each)

// One thread's window: fine planes [begin, end) of every field, plane `begin` at slot 0.
template <int Dim, typename Scalar>
struct PlaneWindow {
  std::vector<Scalar>& storage;
  std::ptrdiff_t plane;  // fine flat indices per plane
  int begin = 0, end = 0;

  Scalar* field(int f) { return storage.data() + f * kWindowPlanes * plane; }
  // Pointers such that p[f][k] is fine flat index k of the window's planes.
  std::array<Scalar*, Dim + 1> indexable() {
    std::array<Scalar*, Dim + 1> p;
    for (int f = 0; f <= Dim; ++f) p[f] = field(f) - begin * plane;
    return p;
  }
  // Moves the window to [first, last): planes it already holds are kept (shifted to the front),
  // the others computed.
  void cover(const Level<Dim, Scalar>& fine, const BandRowPlanes& band_planes, int first,
             int last) {
    if (first >= begin && first < end) {
      const int kept = end - first;
      if (first > begin)
        for (int f = 0; f <= Dim; ++f)
          std::memmove(field(f), field(f) + (first - begin) * plane,
                       sizeof(Scalar) * static_cast<std::size_t>(kept * plane));
      begin = first;
    } else {
      begin = end = first;
    }
    if (last > end) residual_planes(fine, band_planes, end, last, indexable());
    end = last;
  }
};

}  // namespace

template <typename Scalar>
std::size_t ResidualWindows<Scalar>::bytes() const {
  std::size_t sum = 0;
  for (const auto& w : thread) sum += w.capacity() * sizeof(Scalar);
  return sum;
}

template <int Dim, typename Scalar>
void restrict_fresh_residual(const Level<Dim, Scalar>& fine, const BandRowPlanes& band_planes,
                             Level<Dim, Scalar>& coarse, ResidualWindows<Scalar>& windows) {
  for (int f = 0; f <= Dim; ++f) {
    zero_live(coarse.x[f], coarse.live);
    zero_live(coarse.b[f], coarse.live);
  }
  const std::ptrdiff_t plane = fine.lattice.stride(Dim - 1);
  const int fine_planes = fine.lattice.padded(Dim - 1);
  const int coarse_planes = coarse.lattice.padded(Dim - 1);
  const int blocks = (coarse_planes + kCoarsePlaneBlock - 1) / kCoarsePlaneBlock;
  const auto window_size = static_cast<std::size_t>((Dim + 1) * kWindowPlanes * plane);
  windows.thread.resize(static_cast<std::size_t>(omp_get_max_threads()));
#pragma omp parallel
  {
    std::vector<Scalar>& storage = windows.thread[static_cast<std::size_t>(omp_get_thread_num())];
    if (storage.size() < window_size) storage.resize(window_size);
    PlaneWindow<Dim, Scalar> window{storage, plane};
#pragma omp for schedule(dynamic, 1)
    for (int block = 0; block < blocks; ++block) {
      window.begin = window.end = 0;  // a block starts with an empty window
      const int last_plane = std::min(coarse_planes, (block + 1) * kCoarsePlaneBlock);
      for (int z = block * kCoarsePlaneBlock; z < last_plane; ++z) {
        const int first = std::max(0, 2 * z - 2), last = std::min(fine_planes, 2 * z + 1);
        if (first >= last) continue;
        window.cover(fine, band_planes, first, last);
        const auto w = window.indexable();
        std::array<const Scalar*, Dim + 1> r;
        for (int f = 0; f <= Dim; ++f) r[f] = w[f];
        restrict_residual_planes(fine, r, coarse, z, z + 1);
      }
    }
  }
}

#define MGELASTIC_INSTANTIATE(D, S)                                                     \
  template void restrict_fresh_residual<D, S>(const Level<D, S>&, const BandRowPlanes&, \
                                              Level<D, S>&, ResidualWindows<S>&);
MGELASTIC_INSTANTIATE(2, float)
MGELASTIC_INSTANTIATE(2, double)
MGELASTIC_INSTANTIATE(3, float)
MGELASTIC_INSTANTIATE(3, double)
#undef MGELASTIC_INSTANTIATE
template struct ResidualWindows<float>;
template struct ResidualWindows<double>;

}  // namespace mgelastic::grid
