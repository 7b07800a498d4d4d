#include "server/cpu_share.h"

#include <algorithm>
#include <thread>

namespace culinarycut::server {

CpuShare::CpuShare(int cores, bool shared)
    : cores_(cores > 0 ? cores : std::max(1u, std::thread::hardware_concurrency())), shared_(shared) {}

CpuShare::Seat::Seat(CpuShare* share) : share_(share) { share_->running_.fetch_add(1); }

CpuShare::Seat::~Seat() { share_->running_.fetch_sub(1); }

int CpuShare::ThreadsPerStep() const {
  if (!shared_) return 0;
  return std::max(1, cores_ / std::max(1, running_.load()));
}

}  // namespace culinarycut::server
