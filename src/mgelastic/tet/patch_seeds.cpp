#include "mgelastic/tet/patch_seeds.hpp"

#include <algorithm>
#include <random>
#include <string>
#include <utility>

#include "mgelastic/core/error.hpp"

namespace mgelastic::tet {
namespace {

[[noreturn]] void fail_patch_seeds(const std::string& reason) {
  throw Error(reason, ErrorContext{std::string(), -1, "patch_seeds"});
}

}  // namespace

std::vector<int> slow_error_seeds(const Eigen::VectorXd& e, const BlockRowMatrix<double>& pattern,
                                  const std::vector<char>& constrained,
                                  const std::vector<char>& excluded, double threshold,
                                  int max_seeds) {
  const int n = pattern.block_rows();
  if (e.size() != 3 * static_cast<Eigen::Index>(n) || static_cast<int>(constrained.size()) != n ||
      static_cast<int>(excluded.size()) != n)
    fail_patch_seeds("error, constraints or exclusions do not match the pattern's " +
                     std::to_string(n) + " block rows");
  std::vector<double> weight(n);
  double largest = 0.0;
  for (int v = 0; v < n; ++v) {
    weight[v] = constrained[v] != 0 ? 0.0 : e.segment<3>(3 * v).squaredNorm();
    largest = std::max(largest, weight[v]);
  }
  std::vector<std::pair<double, int>> maxima;
  for (int v = 0; v < n; ++v) {
    if (constrained[v] != 0 || excluded[v] != 0 || weight[v] <= 0.0 ||
        weight[v] < threshold * largest)
      continue;
    bool local_maximum = true;
    for (int k = pattern.row_offsets()[v]; k < pattern.row_offsets()[v + 1] && local_maximum; ++k)
      local_maximum = weight[pattern.block_columns()[k]] <= weight[v];
    if (local_maximum) maxima.emplace_back(weight[v], v);
  }
  // Largest first; ties by vertex index so the order is reproducible.
  std::sort(maxima.begin(), maxima.end(), [](const auto& a, const auto& b) {
    return a.first != b.first ? a.first > b.first : a.second < b.second;
  });
  std::vector<int> seeds;
  for (const auto& [w, v] : maxima) {
    if (static_cast<int>(seeds.size()) >= max_seeds) break;
    seeds.push_back(v);
  }
  return seeds;
}

std::vector<std::vector<int>> grow_along_error(const std::vector<int>& seeds,
                                               const Eigen::VectorXd& e,
                                               const BlockRowMatrix<double>& pattern,
                                               const std::vector<char>& constrained, int max_size) {
  const int n = pattern.block_rows();
  if (e.size() != 3 * static_cast<Eigen::Index>(n) || static_cast<int>(constrained.size()) != n)
    fail_patch_seeds("error or constraints do not match the pattern's " + std::to_string(n) +
                     " block rows");
  std::vector<std::vector<int>> patches;
  std::vector<char> member(n, 0);
  for (const int seed : seeds) {
    if (seed < 0 || seed >= n || constrained[seed] != 0) continue;
    std::vector<int> patch{seed};
    member[seed] = 1;
    // Frontier: candidates by (weight, -index); small patches, so a linear scan suffices.
    std::vector<int> frontier;
    const auto add_neighbours = [&](int v) {
      for (int k = pattern.row_offsets()[v]; k < pattern.row_offsets()[v + 1]; ++k) {
        const int j = pattern.block_columns()[k];
        if (constrained[j] == 0 && member[j] == 0 &&
            std::find(frontier.begin(), frontier.end(), j) == frontier.end())
          frontier.push_back(j);
      }
    };
    add_neighbours(seed);
    while (static_cast<int>(patch.size()) < max_size && !frontier.empty()) {
      std::size_t best = 0;
      for (std::size_t c = 1; c < frontier.size(); ++c) {
        const double wc = e.segment<3>(3 * frontier[c]).squaredNorm();
        const double wb = e.segment<3>(3 * frontier[best]).squaredNorm();
        if (wc > wb || (wc == wb && frontier[c] < frontier[best])) best = c;
      }
      const int v = frontier[best];
      frontier.erase(frontier.begin() + static_cast<std::ptrdiff_t>(best));
      patch.push_back(v);
      member[v] = 1;
      add_neighbours(v);
    }
    for (const int v : patch) member[v] = 0;
    patches.push_back(std::move(patch));
  }
  return patches;
}

SlowError slow_error(int vertex_count, const std::vector<char>& constrained,
                     const std::function<void(Eigen::VectorXd&)>& apply_error, int cycles,
                     unsigned random_seed) {
  if (static_cast<int>(constrained.size()) != vertex_count)
    fail_patch_seeds("constraints do not match the " + std::to_string(vertex_count) + " vertices");
  std::mt19937 rng(random_seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  SlowError slow;
  Eigen::VectorXd& e = slow.e;
  e.resize(3 * static_cast<Eigen::Index>(vertex_count));
  for (Eigen::Index i = 0; i < e.size(); ++i) e[i] = constrained[i / 3] != 0 ? 0.0 : uniform(rng);
  double norm = e.norm();
  for (int c = 0; c < cycles && norm > 0.0; ++c) {
    e /= norm;
    apply_error(e);
    norm = e.norm();
    slow.contraction = norm;
  }
  if (norm > 0.0) e /= norm;
  return slow;
}

}  // namespace mgelastic::tet
