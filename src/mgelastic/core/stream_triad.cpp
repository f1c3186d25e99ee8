#include "mgelastic/core/stream_triad.hpp"

#include <algorithm>
#include <memory>

#include "mgelastic/core/timer.hpp"

namespace mgelastic {

double stream_triad_gb_per_s(const TriadOptions& options) {
  const auto n = static_cast<std::ptrdiff_t>(options.bytes_per_array / sizeof(double));
  // Uninitialized storage, first touched by the threads that stream it (page placement).
  std::unique_ptr<double[]> a(new double[n]), b(new double[n]), c(new double[n]);
  double* pa = a.get();
  double* pb = b.get();
  double* pc = c.get();
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    pa[i] = 0.0;
    pb[i] = 1.0;
    pc[i] = 2.0;
  }
  const double s = 3.0;
  double best = 0.0;
  for (int rep = 0; rep < std::max(1, options.repetitions); ++rep) {
    Timer timer;
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t i = 0; i < n; ++i) pa[i] = pb[i] + s * pc[i];
    const double seconds = timer.seconds();
    if (seconds > 0)
      best = std::max(best, 3.0 * sizeof(double) * static_cast<double>(n) / seconds / 1e9);
  }
  // Keeps the stores observable.
  volatile double sink = pa[n / 2];
  (void)sink;
  return best;
}

}  // namespace mgelastic
