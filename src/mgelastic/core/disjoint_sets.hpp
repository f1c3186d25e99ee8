#pragma once
// Union-find over the integers 0..n-1 (connected components of meshes, clusters, coarse cells).
// parent[v] == v marks a root; find_root halves the path as it walks, so repeated queries stay
// near constant time without ranks.
#include <algorithm>
#include <numeric>
#include <vector>

namespace mgelastic {

inline int find_root(std::vector<int>& parent, int v) {
  while (parent[v] != v) v = parent[v] = parent[parent[v]];
  return v;
}

// Disjoint sets whose roots are the smallest member, so roots (and any numbering built on them)
// do not depend on the order of the unions.
class DisjointSets {
 public:
  explicit DisjointSets(int n) : m_parent(n) { std::iota(m_parent.begin(), m_parent.end(), 0); }
  int find(int a) { return find_root(m_parent, a); }
  void unite(int a, int b) {
    a = find(a);
    b = find(b);
    if (a != b) m_parent[std::max(a, b)] = std::min(a, b);
  }

 private:
  std::vector<int> m_parent;
};

}  // namespace mgelastic
