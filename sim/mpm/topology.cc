#include "sim/mpm/topology.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <utility>
#include <vector>

#include "sim/mpm/cut_record.h"

namespace culinarycut::mpm {
namespace {

// Cell coordinates are clamped here so that far-flung (diverged) particles cannot overflow; the
// distance test still uses real positions, so clamping only costs speed, never correctness.
constexpr std::int64_t kMaxCellCoord = std::int64_t{1} << 40;

struct CellCoord {
  std::int64_t x = 0;
  std::int64_t y = 0;
  std::int64_t z = 0;
  bool operator==(const CellCoord& other) const {
    return x == other.x && y == other.y && z == other.z;
  }
};

// The 13 forward neighbours of the half stencil: every pair of adjacent cells is visited once.
// clang-format off
constexpr std::array<std::array<int, 3>, 13> kForwardOffsets = {{
    {1, 0, 0}, {-1, 1, 0}, {0, 1, 0}, {1, 1, 0},
    {-1, -1, 1}, {0, -1, 1}, {1, -1, 1}, {-1, 0, 1}, {0, 0, 1}, {1, 0, 1}, {-1, 1, 1}, {0, 1, 1},
    {1, 1, 1}}};
// clang-format on

std::uint64_t HashCell(const CellCoord& c) {
  std::uint64_t h = static_cast<std::uint64_t>(c.x) * 0x9E3779B97F4A7C15ull;
  h ^= static_cast<std::uint64_t>(c.y) * 0xC2B2AE3D27D4EB4Full + (h << 6) + (h >> 2);
  h ^= static_cast<std::uint64_t>(c.z) * 0x165667B19E3779F9ull + (h << 6) + (h >> 2);
  return h ^ (h >> 29);
}

// Open-addressing map from cell coordinates to compact cell ids, for scenes too spread out for a
// dense grid (ids are given in first-appearance order, so the result is deterministic).
class CellMap {
 public:
  // Empties the map and sizes it for `expected_cells`.
  void Reset(std::size_t expected_cells) {
    std::size_t capacity = 16;
    while (capacity < 2 * expected_cells) capacity *= 2;
    mask_ = capacity - 1;
    keys_.resize(capacity);
    ids_.assign(capacity, -1);
  }

  // Returns the id of `cell`, giving it `new_id` if it is not there yet.
  std::int32_t FindOrInsert(const CellCoord& cell, std::int32_t new_id) {
    std::size_t slot = HashCell(cell) & mask_;
    while (ids_[slot] >= 0) {
      if (keys_[slot] == cell) return ids_[slot];
      slot = (slot + 1) & mask_;
    }
    keys_[slot] = cell;
    ids_[slot] = new_id;
    return new_id;
  }

  std::int32_t Find(const CellCoord& cell) const {
    std::size_t slot = HashCell(cell) & mask_;
    while (ids_[slot] >= 0) {
      if (keys_[slot] == cell) return ids_[slot];
      slot = (slot + 1) & mask_;
    }
    return -1;
  }

 private:
  std::size_t mask_ = 0;
  std::vector<CellCoord> keys_;
  std::vector<std::int32_t> ids_;
};

// Union-find root with path halving.
inline std::int32_t FindRoot(std::vector<std::int32_t>& parent, std::int32_t a) {
  while (parent[a] != a) {
    parent[a] = parent[parent[a]];
    a = parent[a];
  }
  return a;
}

// The active (unbroken, finite) particles in cell order, with the fields the link test reads
// copied contiguously so that the pair loops stream through memory.
template <typename Real>
struct SortedParticles {
  std::vector<std::int32_t> original;  // sorted slot -> particle index
  std::vector<Real> x, y, z;
  std::vector<std::uint16_t> object;
  std::vector<std::int8_t> side;
  std::vector<std::uint32_t> cuts;  // cut records (cut_record.h)
  std::vector<std::uint32_t> cell_start;  // per cell id, plus one past the end
};

// Joins two components by their roots; union by index (the smaller root wins) keeps the forest
// independent of timing. Returns the joined root.
inline std::int32_t Unite(std::vector<std::int32_t>& parent, std::int32_t root_a,
                          std::int32_t root_b) {
  if (root_a == root_b) return root_a;
  if (root_b < root_a) std::swap(root_a, root_b);
  parent[root_b] = root_a;
  return root_a;
}

template <typename Real>
inline bool Linked(const SortedParticles<Real>& s, std::uint32_t a, std::uint32_t b,
                   Real link_distance_sq) {
  const Real dx = s.x[b] - s.x[a], dy = s.y[b] - s.y[a], dz = s.z[b] - s.z[a];
  return dx * dx + dy * dy + dz * dz < link_distance_sq && s.object[b] == s.object[a] &&
         s.side[a] * s.side[b] >= 0 && SameSideOfEveryCut(s.cuts[a], s.cuts[b]);
}

// Links the particles of one cell among themselves. Returns a slot that every particle of the
// cell is now joined to, or -1 where the cell holds more than one component.
template <typename Real>
std::int32_t LinkWithinCell(const SortedParticles<Real>& s, std::uint32_t begin, std::uint32_t end,
                            Real link_distance_sq, std::vector<std::int32_t>& parent) {
  for (std::uint32_t a = begin; a < end; ++a) {
    std::int32_t root = FindRoot(parent, static_cast<std::int32_t>(a));
    for (std::uint32_t b = a + 1; b < end; ++b) {
      if (parent[b] == root || !Linked(s, a, b, link_distance_sq)) continue;
      root = Unite(parent, root, FindRoot(parent, static_cast<std::int32_t>(b)));
    }
  }
  const std::int32_t root = FindRoot(parent, static_cast<std::int32_t>(begin));
  for (std::uint32_t a = begin + 1; a < end; ++a) {
    if (FindRoot(parent, static_cast<std::int32_t>(a)) != root) return -1;
  }
  return static_cast<std::int32_t>(begin);
}

// Links the particles of two neighbouring cells. Where each cell is one component (the usual
// case inside a piece) a single link joins them, so the search stops at the first one.
template <typename Real>
void LinkCellPair(const SortedParticles<Real>& s, std::uint32_t begin_a, std::uint32_t end_a,
                  std::int32_t whole_a, std::uint32_t begin_b, std::uint32_t end_b,
                  std::int32_t whole_b, Real link_distance_sq, std::vector<std::int32_t>& parent) {
  if (whole_a >= 0 && whole_b >= 0) {
    const std::int32_t root_a = FindRoot(parent, whole_a);
    const std::int32_t root_b = FindRoot(parent, whole_b);
    if (root_a == root_b) return;
    for (std::uint32_t a = begin_a; a < end_a; ++a) {
      for (std::uint32_t b = begin_b; b < end_b; ++b) {
        if (Linked(s, a, b, link_distance_sq)) {
          Unite(parent, root_a, root_b);
          return;
        }
      }
    }
    return;
  }
  for (std::uint32_t a = begin_a; a < end_a; ++a) {
    // `root` stays a root through this loop: only this loop's unions change the forest.
    std::int32_t root = FindRoot(parent, static_cast<std::int32_t>(a));
    for (std::uint32_t b = begin_b; b < end_b; ++b) {
      // Already joined: the link would change nothing.
      if (parent[b] == root || !Linked(s, a, b, link_distance_sq)) continue;
      root = Unite(parent, root, FindRoot(parent, static_cast<std::int32_t>(b)));
    }
  }
}

// Links all compatible particle pairs closer than the link distance: first within each cell, then
// between each cell and its 13 forward neighbours. `for_each_cell(f)` calls f(cell id, coords)
// for every cell; `lookup` maps coordinates to a cell id, or -1 where there is none.
template <typename Real, typename ForEachCell, typename Lookup>
void LinkAll(const SortedParticles<Real>& s, Real link_distance_sq, std::size_t cell_count,
             const ForEachCell& for_each_cell, const Lookup& lookup,
             std::vector<std::int32_t>* whole_scratch, std::vector<std::int32_t>& parent) {
  std::vector<std::int32_t>& whole = *whole_scratch;
  whole.assign(cell_count, -1);
  for_each_cell([&](std::int64_t cell, const CellCoord&) {
    const std::uint32_t begin = s.cell_start[cell], end = s.cell_start[cell + 1];
    if (begin != end) whole[cell] = LinkWithinCell(s, begin, end, link_distance_sq, parent);
  });
  for_each_cell([&](std::int64_t cell, const CellCoord& coord) {
    const std::uint32_t begin = s.cell_start[cell], end = s.cell_start[cell + 1];
    if (begin == end) return;
    for (const auto& offset : kForwardOffsets) {
      const std::int64_t other =
          lookup(CellCoord{coord.x + offset[0], coord.y + offset[1], coord.z + offset[2]});
      if (other < 0) continue;
      const std::uint32_t other_begin = s.cell_start[other], other_end = s.cell_start[other + 1];
      if (other_begin == other_end) continue;
      LinkCellPair(s, begin, end, whole[cell], other_begin, other_end, whole[other],
                   link_distance_sq, parent);
    }
  });
}

// Scratch arrays of DetectPieces, kept between calls (see there).
template <typename Real>
struct Workspace {
  std::vector<std::int32_t> active;       // particle indices of unbroken, finite particles
  std::vector<std::uint32_t> cell_of;     // per active particle
  std::vector<std::uint32_t> cursor;      // counting-sort write positions
  std::vector<CellCoord> compact_coords;  // sparse grid only: coordinates per cell id
  CellMap cell_map;                       // sparse grid only
  SortedParticles<Real> sorted;
  std::vector<std::int32_t> parent;  // union-find over sorted slots
  std::vector<std::int32_t> whole;   // per cell: a slot joined to all of it, or -1
  std::vector<std::int32_t> component_size;
  std::vector<std::int32_t> slot_of;  // particle index -> sorted slot, -1 if inactive
  std::vector<std::int32_t> label_of_root;
};

}  // namespace

template <typename Real>
std::vector<Piece> DetectPieces(const TopologyOptions& options, Particles<Real>* particles) {
  if (particles == nullptr) throw std::invalid_argument("DetectPieces: particles is null");
  const double link_distance_m = options.link_distance_m;
  if (!(link_distance_m > 0.0) || !std::isfinite(link_distance_m)) {
    throw std::invalid_argument("TopologyOptions.link_distance_m must be positive and finite");
  }
  Particles<Real>& p = *particles;
  const std::size_t n = p.size();
  if (n > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max())) {
    throw std::invalid_argument("DetectPieces: more than 2^31 - 1 particles");
  }
  p.piece.assign(n, -1);
  if (n == 0) return {};
  // Scratch reused between calls on a thread: at 1M particles fresh pages cost as much as the work.
  thread_local Workspace<Real> ws;
  SortedParticles<Real>& s = ws.sorted;

  // Active particles: unbroken (NaN damage counts as broken) with a finite position.
  ws.active.clear();
  ws.active.reserve(n);
  constexpr double kInf = std::numeric_limits<double>::infinity();
  double lo[3] = {kInf, kInf, kInf};
  double hi[3] = {-kInf, -kInf, -kInf};
  for (std::size_t i = 0; i < n; ++i) {
    if (!(static_cast<double>(p.damage[i]) < options.broken_damage)) continue;
    const double x[3] = {static_cast<double>(p.position[0][i]),
                         static_cast<double>(p.position[1][i]),
                         static_cast<double>(p.position[2][i])};
    if (!std::isfinite(x[0]) || !std::isfinite(x[1]) || !std::isfinite(x[2])) continue;
    ws.active.push_back(static_cast<std::int32_t>(i));
    for (int axis = 0; axis < 3; ++axis) {
      lo[axis] = std::min(lo[axis], x[axis]);
      hi[axis] = std::max(hi[axis], x[axis]);
    }
  }
  const std::size_t m = ws.active.size();

  // Cells of size = link distance. Offsets from `lo` are >= 0, so truncation is floor.
  const double inv_cell_m = 1.0 / link_distance_m;
  auto cell_coord = [&](int axis, std::int32_t i) -> std::int64_t {
    const double t = (static_cast<double>(p.position[axis][i]) - lo[axis]) * inv_cell_m;
    return t < static_cast<double>(kMaxCellCoord) ? static_cast<std::int64_t>(t) : kMaxCellCoord;
  };
  std::int64_t dims[3] = {1, 1, 1};
  double dense_cells = 1.0;
  for (int axis = 0; axis < 3 && m > 0; ++axis) {
    const double t = (hi[axis] - lo[axis]) * inv_cell_m;
    dims[axis] =
        (t < static_cast<double>(kMaxCellCoord) ? static_cast<std::int64_t>(t) : kMaxCellCoord) + 1;
    dense_cells *= static_cast<double>(dims[axis]);
  }
  const std::int64_t nx = dims[0], ny = dims[1], nz = dims[2];
  // A dense grid while it stays within a few cells per particle; a hash map beyond that.
  const bool dense = dense_cells <= 4.0 * static_cast<double>(m) + 65536.0 && dense_cells < 4.0e9;

  ws.cell_of.resize(m);
  ws.compact_coords.clear();
  std::size_t cell_count = 0;
  if (dense) {
    cell_count = static_cast<std::size_t>(dense_cells);
    for (std::size_t k = 0; k < m; ++k) {
      const std::int32_t i = ws.active[k];
      ws.cell_of[k] = static_cast<std::uint32_t>(cell_coord(0, i) +
                                                 nx * (cell_coord(1, i) + ny * cell_coord(2, i)));
    }
  } else {
    ws.cell_map.Reset(m);
    for (std::size_t k = 0; k < m; ++k) {
      const std::int32_t i = ws.active[k];
      const CellCoord coord{cell_coord(0, i), cell_coord(1, i), cell_coord(2, i)};
      const std::int32_t next_id = static_cast<std::int32_t>(ws.compact_coords.size());
      const std::int32_t id = ws.cell_map.FindOrInsert(coord, next_id);
      if (id == next_id) ws.compact_coords.push_back(coord);
      ws.cell_of[k] = static_cast<std::uint32_t>(id);
    }
    cell_count = ws.compact_coords.size();
  }

  // Counting sort by cell (stable, so deterministic), copying the fields the link test reads.
  s.cell_start.assign(cell_count + 1, 0);
  for (std::size_t k = 0; k < m; ++k) ++s.cell_start[ws.cell_of[k] + 1];
  for (std::size_t c = 0; c < cell_count; ++c) s.cell_start[c + 1] += s.cell_start[c];
  ws.cursor.assign(s.cell_start.begin(), s.cell_start.end() - 1);
  s.original.resize(m);
  s.x.resize(m);
  s.y.resize(m);
  s.z.resize(m);
  s.object.resize(m);
  s.side.resize(m);
  s.cuts.resize(m);
  for (std::size_t k = 0; k < m; ++k) {
    const std::int32_t i = ws.active[k];
    const std::uint32_t slot = ws.cursor[ws.cell_of[k]]++;
    s.original[slot] = i;
    s.x[slot] = p.position[0][i];
    s.y[slot] = p.position[1][i];
    s.z[slot] = p.position[2][i];
    s.object[slot] = p.object[i];
    s.side[slot] = options.separate_blade_sides ? p.blade_side[i] : std::int8_t{0};
    s.cuts[slot] = options.separate_cut_sides ? p.cut_sides[i] : 0u;
  }

  // Union-find over sorted slots (cache-friendly); the partition does not depend on the order.
  std::vector<std::int32_t>& parent = ws.parent;
  parent.resize(m);
  std::iota(parent.begin(), parent.end(), 0);
  const Real link_distance_sq = static_cast<Real>(link_distance_m * link_distance_m);
  if (dense) {
    auto for_each_cell = [&](const auto& f) {
      std::int64_t cell = 0;
      for (std::int64_t z = 0; z < nz; ++z) {
        for (std::int64_t y = 0; y < ny; ++y) {
          for (std::int64_t x = 0; x < nx; ++x) f(cell++, CellCoord{x, y, z});
        }
      }
    };
    auto lookup = [&](const CellCoord& c) -> std::int64_t {
      if (c.x < 0 || c.y < 0 || c.z < 0 || c.x >= nx || c.y >= ny || c.z >= nz) return -1;
      return c.x + nx * (c.y + ny * c.z);
    };
    LinkAll(s, link_distance_sq, cell_count, for_each_cell, lookup, &ws.whole, parent);
  } else {
    auto for_each_cell = [&](const auto& f) {
      for (std::size_t cell = 0; cell < cell_count; ++cell) {
        f(static_cast<std::int64_t>(cell), ws.compact_coords[cell]);
      }
    };
    auto lookup = [&](const CellCoord& c) -> std::int64_t { return ws.cell_map.Find(c); };
    LinkAll(s, link_distance_sq, cell_count, for_each_cell, lookup, &ws.whole, parent);
  }

  // Component sizes (compressing every path), then labels in order of each component's lowest
  // particle index. The label pass walks the particles in index order.
  ws.component_size.assign(m, 0);
  for (std::size_t slot = 0; slot < m; ++slot) {
    ++ws.component_size[FindRoot(parent, static_cast<std::int32_t>(slot))];
  }
  ws.slot_of.assign(n, -1);
  for (std::size_t slot = 0; slot < m; ++slot) {
    ws.slot_of[s.original[slot]] = static_cast<std::int32_t>(slot);
  }
  constexpr std::int32_t kUnlabelled = -2;
  ws.label_of_root.assign(m, kUnlabelled);
  const std::int32_t min_count = std::max(1, options.min_piece_particles);
  std::int32_t piece_count = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::int32_t slot = ws.slot_of[i];
    if (slot < 0) continue;
    const std::int32_t root = parent[slot];  // fully compressed by the size pass
    std::int32_t& label = ws.label_of_root[root];
    if (label == kUnlabelled) label = ws.component_size[root] >= min_count ? piece_count++ : -1;
    p.piece[i] = label;
  }

  // Piece statistics, accumulated in particle order so that the sums are reproducible.
  std::vector<Piece> pieces(static_cast<std::size_t>(piece_count));
  std::vector<Eigen::Vector3d> weighted_sum(pieces.size(), Eigen::Vector3d::Zero());
  std::vector<Eigen::Vector3d> plain_sum(pieces.size(), Eigen::Vector3d::Zero());
  for (std::size_t i = 0; i < n; ++i) {
    const std::int32_t label = p.piece[i];
    if (label < 0) continue;
    Piece& piece = pieces[static_cast<std::size_t>(label)];
    const Eigen::Vector3d x(p.position[0][i], p.position[1][i], p.position[2][i]);
    const double mass_kg = p.mass[i];
    if (piece.particle_count == 0) {
      piece.label = label;
      piece.object = p.object[i];
    }
    ++piece.particle_count;
    piece.volume_m3 += static_cast<double>(p.volume[i]);
    piece.mass_kg += mass_kg;
    piece.bounds_m.extend(x);
    piece.rest_bounds_m.extend(Eigen::Vector3d(p.rest_position[0][i], p.rest_position[1][i], p.rest_position[2][i]));
    weighted_sum[static_cast<std::size_t>(label)] += mass_kg * x;
    plain_sum[static_cast<std::size_t>(label)] += x;
  }
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    Piece& piece = pieces[k];
    // Massless pieces (e.g. test setups) fall back to the plain mean.
    piece.centroid_m =
        piece.mass_kg > 0.0
            ? Eigen::Vector3d(weighted_sum[k] / piece.mass_kg)
            : Eigen::Vector3d(plain_sum[k] / static_cast<double>(piece.particle_count));
  }
  return pieces;
}

std::vector<double> CutPositionsAlongAxis(const std::vector<Piece>& pieces, std::uint16_t object,
                                          const Eigen::Vector3d& axis_origin_m,
                                          const Eigen::Vector3d& axis_direction) {
  const double norm = axis_direction.norm();
  if (!(norm > 0.0) || !std::isfinite(norm)) {
    throw std::invalid_argument("CutPositionsAlongAxis: axis_direction must be non-zero");
  }
  const Eigen::Vector3d direction = axis_direction / norm;

  struct Extent {
    double lo, hi;
    std::int32_t label;
  };
  std::vector<Extent> extents;
  for (const Piece& piece : pieces) {
    if (piece.object != object || piece.rest_bounds_m.isEmpty()) continue;
    Extent extent{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
                  piece.label};
    for (int corner = 0; corner < 8; ++corner) {
      const double t =
          (piece.rest_bounds_m.corner(static_cast<Eigen::AlignedBox3d::CornerType>(corner)) -
           axis_origin_m)
              .dot(direction);
      extent.lo = std::min(extent.lo, t);
      extent.hi = std::max(extent.hi, t);
    }
    extents.push_back(extent);
  }
  // By centre, ties by label, so the order never depends on the input order's accidents.
  std::sort(extents.begin(), extents.end(), [](const Extent& a, const Extent& b) {
    const double ca = a.lo + a.hi, cb = b.lo + b.hi;
    if (ca != cb) return ca < cb;
    return a.label < b.label;
  });
  std::vector<double> cuts;
  for (std::size_t k = 1; k < extents.size(); ++k) {
    cuts.push_back(0.5 * (extents[k - 1].hi + extents[k].lo));
  }
  return cuts;
}

template std::vector<Piece> DetectPieces<float>(const TopologyOptions&, Particles<float>*);
template std::vector<Piece> DetectPieces<double>(const TopologyOptions&, Particles<double>*);

}  // namespace culinarycut::mpm
