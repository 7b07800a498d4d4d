#include "sim/mpm/particle_blocks.h"

#include <algorithm>
#include <utility>

#include <omp.h>

#include "sim/mpm/transfer_stencil.h"

namespace culinarycut::mpm {
namespace {

// values[s] <- values[order[s]]: one array's share of a work-sharing loop inside a parallel
// region (no barrier; the caller's region ends with one).
template <typename T>
void PermuteShare(const std::vector<std::uint32_t>& order, const std::vector<T>& values,
                  std::vector<T>* permuted) {
  const T* source = values.data();
  T* target = permuted->data();
#pragma omp for schedule(static) nowait
  for (std::int64_t s = 0; s < static_cast<std::int64_t>(order.size()); ++s) {
    target[s] = source[order[s]];
  }
}

// Permutes each array of the (array, spare) pairs into its spare in one parallel region (one
// fork and join, not one per array), then swaps them: the spares keep their memory for the next
// time, so no page is faulted in again.
template <typename... Pairs>
void PermuteAll(const std::vector<std::uint32_t>& order, int threads, Pairs... pairs) {
  (pairs.second->resize(pairs.first->size()), ...);
#pragma omp parallel num_threads(threads)
  {
    (PermuteShare(order, *pairs.first, pairs.second), ...);
  }
  (pairs.first->swap(*pairs.second), ...);
}

}  // namespace

template <typename Real>
void SortIntoBlocks(const Particles<Real>& p, Real inv_dx, const Eigen::Vector3i& grid_origin,
                    const Eigen::Vector3i& grid_dims, int threads, ParticleBlocks* blocks) {
  const std::size_t n = p.size();
  blocks->counts = (grid_dims.array() + kBlockCells - 1) / kBlockCells;
  const std::size_t block_count = blocks->count();
  blocks->block_of.resize(n);
  blocks->order.resize(n);
  blocks->block_start.assign(block_count + 1, 0);
  // Per-thread histograms over contiguous particle ranges, then one prefix sum over (block,
  // thread): each thread places its range after the earlier threads' particles of the same
  // block, which is the stable order whatever the thread count.
  std::vector<std::uint32_t> offsets(static_cast<std::size_t>(threads) * block_count, 0);
  const Real* position[3] = {p.position[0].data(), p.position[1].data(), p.position[2].data()};
  std::uint32_t* block_of = blocks->block_of.data();
#pragma omp parallel num_threads(threads)
  {
    const int thread = omp_get_thread_num();
    const int team = omp_get_num_threads();
    const std::size_t begin = n * thread / team;
    const std::size_t end = n * (thread + 1) / team;
    std::uint32_t* count = offsets.data() + thread * block_count;
    for (std::size_t q = begin; q < end; ++q) {
      int block[3];
      for (int axis = 0; axis < 3; ++axis) {
        block[axis] = (CellOf(position[axis][q], inv_dx) - grid_origin[axis]) / kBlockCells;
      }
      const std::uint32_t b = static_cast<std::uint32_t>(blocks->Index(block[0], block[1], block[2]));
      block_of[q] = b;
      ++count[b];
    }
#pragma omp barrier
#pragma omp single
    {
      std::uint32_t total = 0;
      for (std::size_t b = 0; b < block_count; ++b) {
        blocks->block_start[b] = total;
        for (int t = 0; t < team; ++t) {
          const std::uint32_t in_range = offsets[t * block_count + b];
          offsets[t * block_count + b] = total;
          total += in_range;
        }
      }
      blocks->block_start[block_count] = total;
    }
    std::uint32_t* next = offsets.data() + thread * block_count;
    for (std::size_t q = begin; q < end; ++q) {
      blocks->order[next[block_of[q]]++] = static_cast<std::uint32_t>(q);
    }
  }
  for (auto& list : blocks->of_colour) list.clear();
  for (std::size_t b = 0; b < block_count; ++b) {
    if (blocks->block_start[b] == blocks->block_start[b + 1]) continue;
    const int bz = static_cast<int>(b % blocks->counts.z());
    const int by = static_cast<int>((b / blocks->counts.z()) % blocks->counts.y());
    const int bx = static_cast<int>(b / (static_cast<std::size_t>(blocks->counts.y()) * blocks->counts.z()));
    blocks->of_colour[(bx & 1) | ((by & 1) << 1) | ((bz & 1) << 2)].push_back(
        static_cast<std::uint32_t>(b));
  }
}

template <typename Real>
void StoreInBlockOrder(int threads, ParticleBlocks* blocks, Particles<Real>* p,
                       Particles<Real>* spare) {
  auto pair = [](auto& array, auto& spare_array) { return std::make_pair(&array, &spare_array); };
  PermuteAll(blocks->order, threads, pair(p->position[0], spare->position[0]),
             pair(p->position[1], spare->position[1]), pair(p->position[2], spare->position[2]),
             pair(p->velocity[0], spare->velocity[0]), pair(p->velocity[1], spare->velocity[1]),
             pair(p->velocity[2], spare->velocity[2]), pair(p->F[0], spare->F[0]),
             pair(p->F[1], spare->F[1]), pair(p->F[2], spare->F[2]), pair(p->F[3], spare->F[3]),
             pair(p->F[4], spare->F[4]), pair(p->F[5], spare->F[5]), pair(p->F[6], spare->F[6]),
             pair(p->F[7], spare->F[7]), pair(p->F[8], spare->F[8]), pair(p->C[0], spare->C[0]),
             pair(p->C[1], spare->C[1]), pair(p->C[2], spare->C[2]), pair(p->C[3], spare->C[3]),
             pair(p->C[4], spare->C[4]), pair(p->C[5], spare->C[5]), pair(p->C[6], spare->C[6]),
             pair(p->C[7], spare->C[7]), pair(p->C[8], spare->C[8]), pair(p->mass, spare->mass),
             pair(p->volume, spare->volume), pair(p->plastic_strain, spare->plastic_strain),
             pair(p->damage, spare->damage), pair(p->piece, spare->piece),
             pair(p->blade_side, spare->blade_side), pair(p->material, spare->material),
             pair(p->object, spare->object), pair(blocks->block_of, blocks->block_of_spare));
  for (std::size_t s = 0; s < blocks->order.size(); ++s) blocks->order[s] = static_cast<std::uint32_t>(s);
}

void MarkBlocksNearSplit(const std::vector<std::size_t>& split_nodes,
                         const Eigen::Vector3i& grid_dims, ParticleBlocks* blocks) {
  blocks->near_split.assign(blocks->count(), 0);
  const Eigen::Vector3i& counts = blocks->counts;
  for (const std::size_t node : split_nodes) {
    const int k = static_cast<int>(node % grid_dims.z());
    const int j = static_cast<int>((node / grid_dims.z()) % grid_dims.y());
    const int i = static_cast<int>(node / (static_cast<std::size_t>(grid_dims.y()) * grid_dims.z()));
    // A particle with base cell b touches nodes b .. b + 2.
    for (int bx = std::max(0, i - 2) / kBlockCells; bx <= std::min(counts.x() - 1, i / kBlockCells); ++bx) {
      for (int by = std::max(0, j - 2) / kBlockCells; by <= std::min(counts.y() - 1, j / kBlockCells); ++by) {
        for (int bz = std::max(0, k - 2) / kBlockCells; bz <= std::min(counts.z() - 1, k / kBlockCells); ++bz) {
          blocks->near_split[blocks->Index(bx, by, bz)] = 1;
        }
      }
    }
  }
}

template void SortIntoBlocks<float>(const Particles<float>&, float, const Eigen::Vector3i&,
                                    const Eigen::Vector3i&, int, ParticleBlocks*);
template void SortIntoBlocks<double>(const Particles<double>&, double, const Eigen::Vector3i&,
                                     const Eigen::Vector3i&, int, ParticleBlocks*);
template void StoreInBlockOrder<float>(int, ParticleBlocks*, Particles<float>*, Particles<float>*);
template void StoreInBlockOrder<double>(int, ParticleBlocks*, Particles<double>*,
                                        Particles<double>*);

}  // namespace culinarycut::mpm
