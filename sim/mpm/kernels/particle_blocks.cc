#include "sim/mpm/kernels/particle_blocks.h"

#include <algorithm>
#include <utility>

#include <omp.h>

#include "sim/mpm/kernels/transfer_stencil.h"

namespace culinarycut::mpm {
namespace {

// Particles whose block indices are computed together before they are counted.
constexpr std::size_t kSortBatch = 256;

// values[s] <- values[order[s]]: one array's share of a work-sharing loop inside a parallel
// region (no barrier; the caller ends with one).
template <typename T>
void PermuteShare(const std::vector<std::uint32_t>& order, const std::vector<T>& values,
                  std::vector<T>* permuted) {
  const T* source = values.data();
  T* target = permuted->data();
  const std::uint32_t* from = order.data();
#pragma omp for schedule(static) nowait
  for (std::int64_t s = 0; s < static_cast<std::int64_t>(order.size()); ++s) {
    target[s] = source[from[s]];
  }
  // Entries past the order (the frozen particles, which are not sorted) stay where they are.
#pragma omp for schedule(static) nowait
  for (std::int64_t s = static_cast<std::int64_t>(order.size()); s < static_cast<std::int64_t>(values.size()); ++s) {
    target[s] = source[s];
  }
}

// Calls f(array, spare array) for every per-particle array the reorder permutes.
template <typename P, typename S, typename B, typename F>
void ForEachParticleArray(P& p, S& spare, B& blocks, F&& f) {
  for (int axis = 0; axis < 3; ++axis) f(p.position[axis], spare.position[axis]);
  for (int axis = 0; axis < 3; ++axis) f(p.velocity[axis], spare.velocity[axis]);
  for (int axis = 0; axis < 3; ++axis) f(p.rest_position[axis], spare.rest_position[axis]);
  for (int k = 0; k < 9; ++k) f(p.F[k], spare.F[k]);
  for (int k = 0; k < 9; ++k) f(p.C[k], spare.C[k]);
  f(p.mass, spare.mass);
  f(p.volume, spare.volume);
  f(p.plastic_strain, spare.plastic_strain);
  for (int k = 0; k < 6; ++k) f(p.maxwell_stress[k], spare.maxwell_stress[k]);
  f(p.damage, spare.damage);
  f(p.piece, spare.piece);
  f(p.blade_side, spare.blade_side);
  f(p.cut_sides, spare.cut_sides);
  f(p.material, spare.material);
  f(p.object, spare.object);
  f(p.activity, spare.activity);
  f(blocks.block_of, blocks.block_of_spare);
}

}  // namespace

template <typename Real>
void CountBlocks(const Particles<Real>& p, std::size_t n, Real inv_dx, const Eigen::Vector3i& grid_origin,
                 const Eigen::Vector3i& grid_dims, ParticleBlocks* blocks) {
  const Eigen::Vector3i counts = BlockCounts(grid_dims);
  const std::size_t block_count = static_cast<std::size_t>(counts.x()) * counts.y() * counts.z();
  // Per-thread histograms over contiguous particle ranges; ListBlocks then makes one prefix sum
  // over (block, thread): each thread places its range after the earlier threads' particles of
  // the same block, which is the stable order whatever the thread count.
  const int thread = omp_get_thread_num();
  const int team = omp_get_num_threads();
  const std::size_t begin = n * thread / team;
  const std::size_t end = n * (thread + 1) / team;
  const Real* const position[3] = {p.position[0].data(), p.position[1].data(), p.position[2].data()};
  std::uint32_t* const block_of = blocks->block_of.data();
  const std::uint32_t count_y = static_cast<std::uint32_t>(counts.y());
  const std::uint32_t count_z = static_cast<std::uint32_t>(counts.z());
  const int origin[3] = {grid_origin.x(), grid_origin.y(), grid_origin.z()};
  std::vector<std::uint32_t>& own = blocks->thread_counts[thread];
  own.assign(block_count, 0);
  std::uint32_t* const count = own.data();
  // Neighbours in memory mostly share a block: count runs, not particles (one increment in
  // memory per run instead of a store-to-load chain per particle).
  std::uint32_t run_block = 0;
  std::uint32_t run = 0;
  for (std::size_t q0 = begin; q0 < end; q0 += kSortBatch) {
    const std::size_t q1 = std::min(end, q0 + kSortBatch);
    for (std::size_t q = q0; q < q1; ++q) {  // vectorises
      std::uint32_t block[3];
      for (int axis = 0; axis < 3; ++axis) {
        block[axis] = static_cast<std::uint32_t>(CellOf(position[axis][q], inv_dx) - origin[axis]) /
                      kBlockCells;
      }
      block_of[q] = (block[0] * count_y + block[1]) * count_z + block[2];
    }
    for (std::size_t q = q0; q < q1; ++q) {
      const std::uint32_t b = block_of[q];
      if (b != run_block) {
        count[run_block] += run;
        run_block = b;
        run = 0;
      }
      ++run;
    }
  }
  if (block_count > 0) count[run_block] += run;
#pragma omp barrier
}

void ListBlocks(const Eigen::Vector3i& grid_dims, ParticleBlocks* blocks) {
  // The team that counted (OpenMP may grant fewer threads than asked for).
  const int team = omp_get_num_threads();
  blocks->counts = BlockCounts(grid_dims);
  const std::size_t block_count = blocks->count();
  blocks->block_start.resize(block_count + 1);
  std::uint32_t total = 0;
  for (std::size_t b = 0; b < block_count; ++b) {
    blocks->block_start[b] = total;
    for (int t = 0; t < team; ++t) {
      std::uint32_t& count = blocks->thread_counts[t][b];
      const std::uint32_t in_range = count;
      count = total;  // from now on the thread's next slot in this block
      total += in_range;
    }
  }
  blocks->block_start[block_count] = total;
  // The non-empty blocks colour by colour, each colour in block order.
  blocks->by_colour.clear();
  const Eigen::Vector3i& counts = blocks->counts;
  for (int colour = 0; colour < 8; ++colour) {
    for (int bx = colour & 1; bx < counts.x(); bx += 2) {
      for (int by = (colour >> 1) & 1; by < counts.y(); by += 2) {
        for (int bz = (colour >> 2) & 1; bz < counts.z(); bz += 2) {
          const std::size_t b = blocks->Index(bx, by, bz);
          if (blocks->block_start[b] != blocks->block_start[b + 1]) {
            blocks->by_colour.push_back(static_cast<std::uint32_t>(b));
          }
        }
      }
    }
  }
}

void PlaceInBlocks(std::size_t n, ParticleBlocks* blocks, std::atomic<int>* threads_done) {
  const int thread = omp_get_thread_num();
  const int team = omp_get_num_threads();
  const std::size_t begin = n * thread / team;
  const std::size_t end = n * (thread + 1) / team;
  const std::uint32_t* const block_of = blocks->block_of.data();
  std::uint32_t* const next = blocks->thread_counts[thread].data();
  std::uint32_t* const order = blocks->order.data();
  std::uint32_t current = 0;
  std::uint32_t slot = blocks->count() > 0 ? next[0] : 0;
  for (std::size_t q = begin; q < end; ++q) {
    const std::uint32_t b = block_of[q];
    if (b != current) {
      next[current] = slot;
      current = b;
      slot = next[b];
    }
    order[slot++] = static_cast<std::uint32_t>(q);
  }
  if (threads_done != nullptr) {
    threads_done->fetch_add(1, std::memory_order_release);
  } else {
#pragma omp barrier
  }
}

template <typename Real>
void SizeBlockOrderSpares(ParticleBlocks* blocks, const Particles<Real>& p, Particles<Real>* spare) {
  ForEachParticleArray(p, *spare, *blocks,
                       [](const auto& array, auto& spare_array) { spare_array.resize(array.size()); });
  blocks->order_spare.resize(blocks->order.size());
}

template <typename Real>
void StoreInBlockOrder(ParticleBlocks* blocks, Particles<Real>* p, Particles<Real>* spare) {
  // Each array into its spare in one work-sharing loop after another, without barriers between;
  // then the spares and the arrays swap: the spares keep their memory for the next time, so no
  // page is faulted in again.
  const std::vector<std::uint32_t>& order = blocks->order;
  ForEachParticleArray(*p, *spare, *blocks,
                       [&order](const auto& array, auto& spare_array) {
                         PermuteShare(order, array, &spare_array);
                       });
  std::uint32_t* const identity = blocks->order_spare.data();
#pragma omp for schedule(static) nowait
  for (std::int64_t s = 0; s < static_cast<std::int64_t>(order.size()); ++s) {
    identity[s] = static_cast<std::uint32_t>(s);
  }
#pragma omp barrier
#pragma omp single
  {
    ForEachParticleArray(*p, *spare, *blocks,
                         [](auto& array, auto& spare_array) { array.swap(spare_array); });
    blocks->order.swap(blocks->order_spare);
  }
}

void MarkBlocksNearSplit(const std::vector<std::size_t>& split_nodes,
                         const Eigen::Vector3i& grid_dims, ParticleBlocks* blocks) {
  const Eigen::Vector3i counts = BlockCounts(grid_dims);
  blocks->near_split.assign(static_cast<std::size_t>(counts.x()) * counts.y() * counts.z(), 0);
  for (const std::size_t node : split_nodes) {
    const int k = static_cast<int>(node % grid_dims.z());
    const int j = static_cast<int>((node / grid_dims.z()) % grid_dims.y());
    const int i = static_cast<int>(node / (static_cast<std::size_t>(grid_dims.y()) * grid_dims.z()));
    // A particle with base cell b touches nodes b .. b + 2.
    for (int bx = std::max(0, i - 2) / kBlockCells; bx <= std::min(counts.x() - 1, i / kBlockCells); ++bx) {
      for (int by = std::max(0, j - 2) / kBlockCells; by <= std::min(counts.y() - 1, j / kBlockCells); ++by) {
        for (int bz = std::max(0, k - 2) / kBlockCells; bz <= std::min(counts.z() - 1, k / kBlockCells); ++bz) {
          blocks->near_split[(static_cast<std::size_t>(bx) * counts.y() + by) * counts.z() + bz] = 1;
        }
      }
    }
  }
}

template void CountBlocks<float>(const Particles<float>&, std::size_t, float, const Eigen::Vector3i&,
                                 const Eigen::Vector3i&, ParticleBlocks*);
template void CountBlocks<double>(const Particles<double>&, std::size_t, double, const Eigen::Vector3i&,
                                  const Eigen::Vector3i&, ParticleBlocks*);
template void SizeBlockOrderSpares<float>(ParticleBlocks*, const Particles<float>&, Particles<float>*);
template void SizeBlockOrderSpares<double>(ParticleBlocks*, const Particles<double>&,
                                           Particles<double>*);
template void StoreInBlockOrder<float>(ParticleBlocks*, Particles<float>*, Particles<float>*);
template void StoreInBlockOrder<double>(ParticleBlocks*, Particles<double>*, Particles<double>*);

}  // namespace culinarycut::mpm
