#include "mgelastic/tet/galerkin_product.hpp"

#include <algorithm>
#include <string>

#include "mgelastic/core/error.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace mgelastic::tet {
namespace {

[[noreturn]] void fail_galerkin(const std::string& reason) {
  throw Error(reason, ErrorContext{std::string(), -1, "Galerkin product"});
}

void check_sizes(const BlockRowMatrix<double>& fine, const Prolongation& p) {
  if (fine.block_rows() != p.fine_vertex_count())
    fail_galerkin("prolongation has " + std::to_string(p.fine_vertex_count()) +
                  " fine vertices, matrix " + std::to_string(fine.block_rows()) + " block rows");
}

// Pairs ahead whose destination block the walk prefetches, on coarse matrices of at least
// kPrefetchBytes.
constexpr int kPrefetchPairs = 8;
constexpr std::size_t kPrefetchBytes = 16u << 20;

// Streams above this many pairs in total are walked in parallel.
constexpr std::size_t kMinParallelPairs = 20000;

}  // namespace

BlockRowMatrix<double> galerkin_pattern(const BlockRowMatrix<double>& fine, const Prolongation& p) {
  check_sizes(fine, p);
  const int nc = p.coarse_vertex_count;
  std::vector<std::vector<int>> columns(nc);
  for (int a = 0; a < nc; ++a) columns[a].push_back(a);
  for (int i = 0; i < fine.block_rows(); ++i)
    for (int k = fine.row_offsets()[i]; k < fine.row_offsets()[i + 1]; ++k) {
      const int j = fine.block_columns()[k];
      for (int s = 0; s < 4; ++s) {
        if (p.weights[i][s] == 0.0) continue;
        std::vector<int>& row = columns[p.vertices[i][s]];
        for (int t = 0; t < 4; ++t)
          if (p.weights[j][t] != 0.0) row.push_back(p.vertices[j][t]);
      }
      // Keep the per-row lists short.
    }
  std::vector<int> offsets(nc + 1, 0);
  std::vector<int> block_columns;
  for (int a = 0; a < nc; ++a) {
    std::sort(columns[a].begin(), columns[a].end());
    columns[a].erase(std::unique(columns[a].begin(), columns[a].end()), columns[a].end());
    block_columns.insert(block_columns.end(), columns[a].begin(), columns[a].end());
    offsets[a + 1] = static_cast<int>(block_columns.size());
    std::vector<int>().swap(columns[a]);
  }
  return BlockRowMatrix<double>(std::move(offsets), std::move(block_columns));
}

void galerkin_naive(const BlockRowMatrix<double>& fine, const Prolongation& p,
                    BlockRowMatrix<double>& coarse) {
  check_sizes(fine, p);
  coarse.set_zero();
  for (int i = 0; i < fine.block_rows(); ++i)
    for (int k = fine.row_offsets()[i]; k < fine.row_offsets()[i + 1]; ++k) {
      const int j = fine.block_columns()[k];
      for (int s = 0; s < 4; ++s) {
        if (p.weights[i][s] == 0.0) continue;
        for (int t = 0; t < 4; ++t) {
          if (p.weights[j][t] == 0.0) continue;
          const int e = coarse.find(p.vertices[i][s], p.vertices[j][t]);
          if (e < 0) fail_galerkin("coarse pattern misses a block of P^T K P");
          coarse.block(e) += (p.weights[i][s] * p.weights[j][t]) * fine.block(k);
        }
      }
    }
}

void GalerkinStream::encode_block(std::vector<std::uint8_t>& control, int pairs) {
  control.push_back(static_cast<std::uint8_t>(0x80 | std::min(pairs, 127)));
  for (pairs -= std::min(pairs, 127); pairs > 0; pairs -= std::min(pairs, 127))
    control.push_back(static_cast<std::uint8_t>(std::min(pairs, 127)));
}

GalerkinStream::GalerkinStream(const BlockRowMatrix<double>& fine, const Prolongation& p,
                               const BlockRowMatrix<double>& coarse, int streams)
    : m_fine_blocks(fine.block_count()), m_coarse_blocks(coarse.block_count()) {
  check_sizes(fine, p);
  if (coarse.block_rows() != p.coarse_vertex_count)
    fail_galerkin("coarse matrix size differs from P");
#ifdef _OPENMP
  if (streams <= 0) streams = omp_get_max_threads();
#endif
  streams = std::max(1, std::min(streams, std::max(1, coarse.block_rows())));
  // Pairs per destination row, to balance the partitions.
  const int nc = coarse.block_rows();
  std::vector<long long> row_pairs(nc, 0);
  long long total = 0;
  for (int i = 0; i < fine.block_rows(); ++i)
    for (int k = fine.row_offsets()[i]; k < fine.row_offsets()[i + 1]; ++k) {
      const int j = fine.block_columns()[k];
      for (int s = 0; s < 4; ++s) {
        if (p.weights[i][s] == 0.0) continue;
        for (int t = 0; t < 4; ++t)
          if (p.weights[j][t] != 0.0 && p.vertices[j][t] >= p.vertices[i][s]) {
            ++row_pairs[p.vertices[i][s]];
            ++total;
          }
      }
    }
  m_streams.resize(streams);
  {
    int row = 0;
    long long done = 0;
    for (int s = 0; s < streams; ++s) {
      m_streams[s].row_begin = row;
      const long long target = total * (s + 1) / streams;
      while (row < nc && (s == streams - 1 || done + row_pairs[row] / 2 <= target))
        done += row_pairs[row++];
      m_streams[s].row_end = row;
    }
  }
  // Algorithm 1, one stream per destination range, built in parallel (each stream is private).
  char missing = 0;
#pragma omp parallel for schedule(static, 1) reduction(| : missing)
  for (int s = 0; s < streams; ++s) {
    Stream& stream = m_streams[s];
    stream.first_block = -1;
    int previous = -1;  // last block of K that has a control byte
    for (int i = 0; i < fine.block_rows(); ++i) {
      bool feeds = false;
      for (int u = 0; u < 4; ++u) {
        const int a = p.vertices[i][u];
        feeds |= p.weights[i][u] != 0.0 && a >= stream.row_begin && a < stream.row_end;
      }
      if (!feeds) continue;
      for (int k = fine.row_offsets()[i]; k < fine.row_offsets()[i + 1]; ++k) {
        const int j = fine.block_columns()[k];
        int pairs = 0;
        for (int u = 0; u < 4; ++u) {
          const int a = p.vertices[i][u];
          if (p.weights[i][u] == 0.0 || a < stream.row_begin || a >= stream.row_end) continue;
          for (int t = 0; t < 4; ++t) {
            // Upper blocks only (a <= b); the lower ones are their transposes.
            if (p.weights[j][t] == 0.0 || p.vertices[j][t] < a) continue;
            const int e = coarse.find(a, p.vertices[j][t]);
            if (e < 0) {
              missing = 1;  // thrown after the parallel region
              continue;
            }
            stream.weights.push_back(p.weights[i][u] * p.weights[j][t]);
            stream.destinations.push_back(e);
            ++pairs;
          }
        }
        if (pairs == 0) continue;
        // Blocks of K skipped since the previous encoded one cost one fetch byte each.
        if (stream.first_block < 0)
          stream.first_block = previous = k;
        else
          for (++previous; previous < k; ++previous) stream.control.push_back(0x80);
        encode_block(stream.control, pairs);
      }
    }
    if (stream.first_block < 0) stream.first_block = 0;
    stream.control.shrink_to_fit();
    stream.weights.shrink_to_fit();
    stream.destinations.shrink_to_fit();
  }
  if (missing != 0) fail_galerkin("coarse pattern misses a block of P^T K P");
  m_mirror.assign(m_coarse_blocks, -1);
  for (int a = 0; a < nc; ++a)
    for (int e = coarse.row_offsets()[a]; e < coarse.row_offsets()[a + 1]; ++e) {
      const int b = coarse.block_columns()[e];
      if (b >= a) continue;
      m_mirror[e] = coarse.find(b, a);
      if (m_mirror[e] < 0) fail_galerkin("coarse pattern is not symmetric");
    }
}

void GalerkinStream::update(const BlockRowMatrix<double>& fine,
                            BlockRowMatrix<double>& coarse) const {
  if (fine.block_count() != m_fine_blocks || coarse.block_count() != m_coarse_blocks)
    fail_galerkin("matrices differ from the patterns the streams were built for");
  const int streams = stream_count();
  const bool prefetch =
      static_cast<std::size_t>(m_coarse_blocks) * sizeof(Eigen::Matrix3d) >= kPrefetchBytes;
#pragma omp parallel if (streams > 1 && pair_count() >= kMinParallelPairs)
  {
#pragma omp for schedule(static, 1)
    for (int s = 0; s < streams; ++s) {
      const Stream& stream = m_streams[s];
      // Each stream owns the blocks of its destination rows: zero them, then walk.
      for (int e = coarse.row_offsets()[stream.row_begin]; e < coarse.row_offsets()[stream.row_end];
           ++e)
        coarse.block(e).setZero();
      const double* weight = stream.weights.data();
      const std::int32_t* destination = stream.destinations.data();
      // On large levels the destination blocks are scattered over an E beyond the caches: fetch
      // the one kPrefetchPairs ahead while this one is updated (measured at 527k tets: stream
      // 145 -> 125 ms under load; no gain measurable on small levels, so only there).
      const std::ptrdiff_t pairs = static_cast<std::ptrdiff_t>(stream.destinations.size());
      const std::int32_t* prefetch_end =
          destination + (prefetch ? std::max<std::ptrdiff_t>(0, pairs - kPrefetchPairs) : 0);
      // The fetched block is copied to a local (registers) and E addressed through a hoisted
      // pointer: the compiler cannot prove that the stores into E miss K, and otherwise reloads
      // both on every pair.
      static_assert(sizeof(Eigen::Matrix3d) == 9 * sizeof(double), "blocks are contiguous");
      double* const values = stream.control.empty() ? nullptr : coarse.block(0).data();
      int k = stream.first_block - 1;
      for (const std::uint8_t c : stream.control) {
        k += c >> 7;  // fetch-next bit
        // The block's 9 values as two 4-vectors and a scalar (whole AVX registers).
        const double* block = fine.block(k).data();
        const Eigen::Vector4d head(block), middle(block + 4);
        const double last = block[8];
        for (int n = c & 0x7f; n > 0; --n, ++weight, ++destination) {
          if (destination < prefetch_end)
            __builtin_prefetch(
                values + 9 * static_cast<std::ptrdiff_t>(destination[kPrefetchPairs]), 1);
          double* const target = values + 9 * static_cast<std::ptrdiff_t>(*destination);
          const double w = *weight;
          Eigen::Map<Eigen::Vector4d>(target) += w * head;
          Eigen::Map<Eigen::Vector4d>(target + 4) += w * middle;
          target[8] += w * last;
        }
      }
    }
    // Lower blocks from the upper ones (after the barrier: their rows may be another stream's).
#pragma omp for schedule(static, 1)
    for (int s = 0; s < streams; ++s)
      for (int e = coarse.row_offsets()[m_streams[s].row_begin];
           e < coarse.row_offsets()[m_streams[s].row_end]; ++e)
        if (m_mirror[e] >= 0) coarse.block(e) = coarse.block(m_mirror[e]).transpose();
  }
}

std::size_t GalerkinStream::pair_count() const {
  std::size_t pairs = 0;
  for (const Stream& s : m_streams) pairs += s.weights.size();
  return pairs;
}

std::size_t GalerkinStream::memory_bytes() const {
  std::size_t bytes = 0;
  for (const Stream& s : m_streams)
    bytes += s.control.size() + s.weights.size() * sizeof(double) +
             s.destinations.size() * sizeof(std::int32_t);
  return bytes + m_mirror.size() * sizeof(int);
}

}  // namespace mgelastic::tet
