#pragma once
// Adaptive seeding of feature patches from the V-cycle's own slow error (an adaptive / bootstrap
// idea as in adaptive AMG): at setup, a few V-cycles on A e = 0 from a random start are power
// iterations of the error operator E = I - B A, so e ends up dominated by the modes the cycle
// reduces worst. Where |e_v|^2 concentrates (graph-local maxima of |e_v|^2 above a share of its
// maximum) the cycle needs help: a feature patch (feature_patches.hpp) is seeded there and grown
// along the error (the free neighbour with the largest |e_v|^2 next), so that it covers the
// mode's support rather than a fixed graph ball. Repeated for a few rounds, each round on the
// cycle with the patches found so far.
//
// Data: e is 3N vertex-major (as the multigrid's vectors); the pattern's block graph defines the
// neighbours of a vertex. Deterministic: fixed random start, and the cycle is thread-count
// independent, so the seeds are too.
#include <Eigen/Core>
#include <functional>
#include <vector>

#include "mgelastic/tet/brc_matrix.hpp"

namespace mgelastic::tet {

struct AdaptivePatchSettings {
  int rounds = 0;  // at most this many rounds; 0 = off
  int cycles = 6;  // V-cycles (power iterations) per round
  // Stop once the power iteration's last contraction |E e| / |e| is <= this (the cycle is then
  // fast enough on its slowest modes found).
  double target_contraction = 0.1;
  double threshold = 0.01;          // seeds: local maxima of |e_v|^2 >= threshold x the largest
  double max_seed_fraction = 0.01;  // at most this fraction of the vertices seeded per round
  int max_size = 30;                // vertices per adaptive patch
  unsigned random_seed = 1;
};

// Vertices where the error e concentrates: free vertices whose |e_v|^2 is >= that of every matrix
// neighbour and >= threshold x max_v |e_v|^2, largest first, at most max_seeds. Vertices with
// `excluded[v]` != 0 (e.g. already seeds) are skipped. Throws Error on size mismatches.
std::vector<int> slow_error_seeds(const Eigen::VectorXd& e, const BlockRowMatrix<double>& pattern,
                                  const std::vector<char>& constrained,
                                  const std::vector<char>& excluded, double threshold,
                                  int max_seeds);

// Patches of at most max_size vertices grown from each seed along the error: starting from the
// seed, repeatedly the free matrix neighbour of the patch with the largest |e_v|^2 (ties: lower
// index) joins. Throws Error on size mismatches.
std::vector<std::vector<int>> grow_along_error(const std::vector<int>& seeds,
                                               const Eigen::VectorXd& e,
                                               const BlockRowMatrix<double>& pattern,
                                               const std::vector<char>& constrained, int max_size);

// A slow error of a cycle: `cycles` applications of apply_error (e <- E e, e.g. one V-cycle on
// A e = 0) to a seeded random vector (zero on constrained vertices), normalized after each;
// `contraction` is |E e| / |e| of the last application (a lower bound of the slowest mode's).
struct SlowError {
  Eigen::VectorXd e;
  double contraction = 0.0;
};
SlowError slow_error(int vertex_count, const std::vector<char>& constrained,
                     const std::function<void(Eigen::VectorXd&)>& apply_error, int cycles,
                     unsigned random_seed);

}  // namespace mgelastic::tet
