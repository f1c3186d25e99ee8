#pragma once
// Repairs of a voxel set that the staggered discretization (Zhu et al. 2010, Sec. 5.1) needs to
// be well posed, for the finest lattice (voxelization) and every coarse level (grid coarsening).
//
// Why: with traction-free boundaries the discrete strain energy only sees
//   * the normal strain of a cell along e_i when both its e_i neighbors are occupied, and
//   * the shear strain at an edge (a node in 2D) when all four cells around it are occupied;
// every other stress is a boundary stress, eliminated as zero. Hence
//   * a part one cell thick has no shear stress across it (all such edges are boundary edges)
//     and no unknown displacement normal to it: it carries no bending;
//   * a fully occupied 2^d block moves rigidly when unstrained (3D: its 6 inner shear edges
//     hold its 12 inner faces up to the 6 rigid motions; 2D: 1 node, 4 faces, 3 motions);
//   * two full blocks sharing a 2^(d-1) x 1 half (offset by one cell along one axis) move as
//     one rigid body (the shared faces and the normal strains across the half fix their
//     relative motion), and so does every union of full blocks chained that way;
//   * thick parts whose full blocks are not so chained, joined through a single cell face or
//     a strip one cell wide, rotate about that hinge (the shear edges along it are boundary
//     edges): the system is singular although the cells are face-connected.
// When every occupied cell lies in a full block, every unknown face is tied to a block (it lies
// inside one, or the normal strain of its cell ties it to a face inside the cell's block), so
// one chained union per face-connected piece leaves no strain-free mode but the rigid motions
// of the pieces.
//
// Data: `occupied` is a box of dims[0] x ... x dims[Dim-1] cells, x fastest, nonzero = occupied.
#include <Eigen/Core>
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <numeric>
#include <queue>
#include <unordered_map>
#include <utility>
#include <vector>

namespace mgelastic::geometry {

template <int Dim>
using CellCoords = Eigen::Matrix<int, Dim, 1>;

namespace rigid_blocks_detail {

template <int Dim>
std::size_t flat(const CellCoords<Dim>& dims, const CellCoords<Dim>& c) {
  std::size_t k = 0;
  for (int a = Dim - 1; a >= 0; --a) k = k * static_cast<std::size_t>(dims[a]) + c[a];
  return k;
}

template <int Dim>
CellCoords<Dim> unflat(const CellCoords<Dim>& dims, std::size_t k) {
  CellCoords<Dim> c;
  for (int a = 0; a < Dim; ++a) {
    c[a] = static_cast<int>(k % static_cast<std::size_t>(dims[a]));
    k /= static_cast<std::size_t>(dims[a]);
  }
  return c;
}

template <int Dim>
bool inside(const CellCoords<Dim>& dims, const CellCoords<Dim>& c) {
  return (c.array() >= 0).all() && (c.array() < dims.array()).all();
}

// Corner `bits` (bit a = +1 along axis a) of the block whose lower corner is `corner`.
template <int Dim>
CellCoords<Dim> corner_cell(const CellCoords<Dim>& corner, int bits) {
  CellCoords<Dim> c = corner;
  for (int a = 0; a < Dim; ++a) c[a] += (bits >> a) & 1;
  return c;
}

// Whether the 2^d block whose lower corner is `corner` is fully occupied.
template <int Dim>
bool full_block(const CellCoords<Dim>& dims, const std::vector<std::uint8_t>& occupied,
                const CellCoords<Dim>& corner) {
  for (int bits = 0; bits < (1 << Dim); ++bits)
    if (!occupied[flat<Dim>(dims, corner_cell<Dim>(corner, bits))]) return false;
  return true;
}

// Gives `label` to the face-connected piece of occupied, unlabeled cells around `seed`, run by
// run along x (the stack holds a seed per run of the piece's frontier, and no coordinates are
// divided out of flat indices).
template <int Dim>
void label_piece(const CellCoords<Dim>& dims, const std::vector<std::uint8_t>& occupied,
                 const CellCoords<Dim>& seed, std::uint32_t label,
                 std::vector<std::uint32_t>& piece) {
  constexpr std::uint32_t none = std::numeric_limits<std::uint32_t>::max();
  const auto open = [&](std::size_t k) { return occupied[k] && piece[k] == none; };
  std::vector<CellCoords<Dim>> stack{seed};
  while (!stack.empty()) {
    CellCoords<Dim> c = stack.back();
    stack.pop_back();
    const std::size_t k = flat<Dim>(dims, c);
    if (!open(k)) continue;
    int lo = c[0], hi = c[0];
    while (lo > 0 && open(k - static_cast<std::size_t>(c[0] - lo + 1))) --lo;
    while (hi + 1 < dims[0] && open(k + static_cast<std::size_t>(hi + 1 - c[0]))) ++hi;
    const std::size_t row = k - static_cast<std::size_t>(c[0]);
    for (int i = lo; i <= hi; ++i) piece[row + static_cast<std::size_t>(i)] = label;
    for (int a = 1; a < Dim; ++a)
      for (int sign : {-1, 1}) {
        CellCoords<Dim> t = c;
        t[a] += sign;
        if (t[a] < 0 || t[a] >= dims[a]) continue;
        t[0] = 0;
        const std::size_t base = flat<Dim>(dims, t);
        for (int i = lo; i <= hi; ++i)
          if (open(base + static_cast<std::size_t>(i)) &&
              (i == lo || !open(base + static_cast<std::size_t>(i) - 1))) {
            t[0] = i;
            stack.push_back(t);
          }
      }
  }
}

// Calls visit(k, c) for every cell of a box of `dims` in storage order (x fastest), its
// coordinates counted along instead of divided out of k (unflat's divisions made the passes
// over every block position of a 256-cell lattice a good part of the voxelization).
template <int Dim, typename Visit>
void for_each_cell(const CellCoords<Dim>& dims, Visit&& visit) {
  if ((dims.array() <= 0).any()) return;
  std::size_t count = 1;
  for (int a = 0; a < Dim; ++a) count *= static_cast<std::size_t>(dims[a]);
  CellCoords<Dim> c = CellCoords<Dim>::Zero();
  for (std::size_t k = 0; k < count; ++k) {
    visit(k, c);
    for (int a = 0; a < Dim && ++c[a] == dims[a]; ++a) c[a] = 0;
  }
}

}  // namespace rigid_blocks_detail

// Makes every occupied cell part of a fully occupied block of size^d cells, filling, per cell in
// storage order, the block (among those containing it, lower corners first) that already holds
// the most occupied cells. size 2: the rigidity rule above; size 3: every part is at least three
// cells thick, so its coarsening (any sub-cell occupied) has every cell in a full 2^d block.
// Returns the number of cells added.
template <int Dim>
int thicken_to_full_blocks(const CellCoords<Dim>& dims, std::vector<std::uint8_t>& occupied,
                           int size = 2) {
  namespace d = rigid_blocks_detail;
  int cells_per_block = 1;
  for (int a = 0; a < Dim; ++a) cells_per_block *= size;
  // Offset number q -> offset vector in [0, size)^Dim, x fastest.
  std::vector<CellCoords<Dim>> offsets(static_cast<std::size_t>(cells_per_block));
  for (int q = 0; q < cells_per_block; ++q)
    for (int a = 0, rest = q; a < Dim; ++a) offsets[q][a] = rest % size, rest /= size;
  const auto offset = [&](int q) { return offsets[static_cast<std::size_t>(q)]; };
  // The same offsets in storage order: a block's cells are its corner's index plus these.
  std::vector<std::size_t> shift(offsets.size());
  for (std::size_t q = 0; q < offsets.size(); ++q) shift[q] = d::flat<Dim>(dims, offsets[q]);
  int added = 0;
  d::for_each_cell<Dim>(dims, [&](std::size_t k, const CellCoords<Dim>& cell) {
    if (!occupied[k]) return;
    std::size_t best = 0;
    int best_count = -1;
    bool full = false;
    for (int b = 0; b < cells_per_block && !full; ++b) {
      const CellCoords<Dim> corner = cell - offset(b);
      if ((corner.array() < 0).any() || (corner.array() + size > dims.array()).any()) continue;
      const std::size_t first = k - shift[static_cast<std::size_t>(b)];
      int count = 0;
      for (const std::size_t s : shift) count += occupied[first + s] != 0;
      full = count == cells_per_block;
      if (count > best_count) best_count = count, best = first;
    }
    if (full || best_count < 0) return;
    for (const std::size_t s : shift) {
      std::uint8_t& o = occupied[best + s];
      added += o == 0;
      o = 1;
    }
  });
  return added;
}

// Hinge repair: in every face-connected piece, chains all fully occupied 2^d blocks into one
// union of blocks sharing 2^(d-1) x 1 halves, filling the fewest cells found by Dijkstra over
// block positions (entering a position costs its empty cells; positions holding cells of
// another piece are closed, so separate pieces stay separate). Grows from the piece's largest
// union and fills the cheapest chain of blocks to each other union as it is reached. Expects
// thicken_to_full_blocks() first (cells in no full block are not considered). Returns the
// number of cells added.
template <int Dim>
int connect_full_blocks(const CellCoords<Dim>& dims, std::vector<std::uint8_t>& occupied) {
  namespace d = rigid_blocks_detail;
  constexpr int corners = 1 << Dim;
  constexpr std::uint32_t none = std::numeric_limits<std::uint32_t>::max();
  if ((dims.array() < 2).any()) return 0;
  const CellCoords<Dim> m = dims.array() - 1;  // block positions (lower corners) per axis
  const std::size_t blocks = static_cast<std::size_t>(m.prod());

  // Face-connected pieces of the occupied set, numbered by their first cell in storage order.
  std::vector<std::uint32_t> piece(occupied.size(), none);
  std::uint32_t pieces = 0;
  d::for_each_cell<Dim>(dims, [&](std::size_t k, const CellCoords<Dim>& c) {
    if (occupied[k] && piece[k] == none) d::label_piece<Dim>(dims, occupied, c, pieces++, piece);
  });
  const auto piece_of_block = [&](std::size_t q) {
    return piece[d::flat<Dim>(dims, d::unflat<Dim>(m, q))];
  };

  // Unions of full blocks (union-find), joined across shared halves.
  std::vector<std::uint8_t> full(blocks, 0);
  d::for_each_cell<Dim>(m, [&](std::size_t q, const CellCoords<Dim>& corner) {
    full[q] = d::full_block<Dim>(dims, occupied, corner);
  });
  std::vector<std::uint32_t> parent(blocks);
  std::iota(parent.begin(), parent.end(), 0u);
  const auto find = [&](std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  const auto unite = [&](std::size_t a, std::size_t b) {
    const std::uint32_t ra = find(static_cast<std::uint32_t>(a));
    const std::uint32_t rb = find(static_cast<std::uint32_t>(b));
    if (ra != rb) parent[std::max(ra, rb)] = std::min(ra, rb);
  };
  d::for_each_cell<Dim>(m, [&](std::size_t q, const CellCoords<Dim>& corner) {
    if (!full[q]) return;
    for (int a = 0; a < Dim; ++a) {
      CellCoords<Dim> c = corner;
      c[a] += 1;
      if (d::inside<Dim>(m, c) && full[d::flat<Dim>(m, c)]) unite(q, d::flat<Dim>(m, c));
    }
  });
  // Blocks of each union (keyed by its root), the number of unions and the largest per piece.
  std::unordered_map<std::uint32_t, std::vector<std::uint32_t>> members;
  for (std::size_t q = 0; q < blocks; ++q)
    if (full[q])
      members[find(static_cast<std::uint32_t>(q))].push_back(static_cast<std::uint32_t>(q));
  std::vector<std::uint32_t> largest(pieces, none);
  std::vector<int> unions(pieces, 0);
  for (const auto& [r, list] : members) {
    const std::uint32_t p = piece_of_block(r);
    ++unions[p];
    if (largest[p] == none || list.size() > members.at(largest[p]).size() ||
        (list.size() == members.at(largest[p]).size() && r < largest[p]))
      largest[p] = r;
  }

  int added = 0;
  std::vector<int> cost;
  std::vector<std::uint32_t> previous;
  for (std::uint32_t p = 0; p < pieces; ++p) {
    if (unions[p] < 2) continue;
    cost.assign(blocks, std::numeric_limits<int>::max());
    previous.assign(blocks, none);
    using Entry = std::pair<int, std::uint32_t>;
    std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
    // A seed whose neighbors are all full blocks of its union relaxes nothing when popped
    // (they are seeds too, at cost 0, before the first pop): it is not queued (most of a
    // union's blocks; the queue's order, and so the result, are the same).
    const auto seed = [&](std::uint32_t q) {
      cost[q] = 0;
      previous[q] = none;
      const CellCoords<Dim> b = d::unflat<Dim>(m, q);
      const std::uint32_t own = find(q);
      for (int a = 0; a < Dim; ++a)
        for (int sign : {-1, 1}) {
          CellCoords<Dim> c = b;
          c[a] += sign;
          if (!d::inside<Dim>(m, c)) continue;
          const auto qc = static_cast<std::uint32_t>(d::flat<Dim>(m, c));
          if (!full[qc] || find(qc) != own) {
            queue.emplace(0, q);
            return;
          }
        }
    };
    for (std::uint32_t q : members.at(largest[p])) seed(q);
    std::uint32_t root = find(largest[p]);
    int joined = 1;
    while (!queue.empty() && joined < unions[p]) {
      const auto [distance, q] = queue.top();
      queue.pop();
      if (distance > cost[q]) continue;
      if (full[q] && find(q) != root) {
        // Another union reached: fill the chain of blocks back to the grown set, join both.
        const std::uint32_t reached = find(q);
        std::vector<std::uint32_t> chain;
        for (std::uint32_t c = previous[q]; c != none && cost[c] > 0; c = previous[c])
          chain.push_back(c);
        for (std::uint32_t c : chain) {
          for (int bits = 0; bits < corners; ++bits) {
            const std::size_t cell =
                d::flat<Dim>(dims, d::corner_cell<Dim>(d::unflat<Dim>(m, c), bits));
            added += occupied[cell] == 0;
            occupied[cell] = 1;
            piece[cell] = p;
          }
          full[c] = 1;
          unite(c, root);
        }
        unite(q, root);
        root = find(root);
        joined += members.count(reached) > 0;
        const auto newcomers = members.find(reached);
        if (newcomers != members.end())
          for (std::uint32_t c : newcomers->second) seed(c);
        for (std::uint32_t c : chain) seed(c);
        continue;
      }
      const CellCoords<Dim> b = d::unflat<Dim>(m, q);
      for (int a = 0; a < Dim; ++a)
        for (int sign : {-1, 1}) {
          CellCoords<Dim> c = b;
          c[a] += sign;
          if (!d::inside<Dim>(m, c)) continue;
          int empty = 0;
          bool closed = false;
          for (int bits = 0; bits < corners && !closed; ++bits) {
            const std::size_t cell = d::flat<Dim>(dims, d::corner_cell<Dim>(c, bits));
            empty += occupied[cell] == 0;
            closed = piece[cell] != none && piece[cell] != p;
          }
          if (closed) continue;
          const std::size_t qc = d::flat<Dim>(m, c);
          if (distance + empty < cost[qc]) {
            cost[qc] = distance + empty;
            previous[qc] = q;
            queue.emplace(cost[qc], static_cast<std::uint32_t>(qc));
          }
        }
    }
  }
  return added;
}

}  // namespace mgelastic::geometry
