// The machine's cores shared among the Steps running at once in one server. With one Step running it
// may use every core its food can use; with n at once each gets cores / n (at least one), asked again
// before every physics step, so sessions stepped in parallel (a runner's workers, several clients)
// never ask for more threads than there are cores (OpenMP teams that outnumber the cores wait at every
// barrier for a thread the kernel has parked). The results are the same bits on any team size.
#pragma once

#include <atomic>

namespace culinarycut::server {

class CpuShare {
 public:
  // `cores`: how many this server's Steps share (0: the machine's); `shared` false: every Step
  // takes the threads its food model chose, however many run at once (the behaviour before sharing).
  CpuShare(int cores, bool shared);

  // Held by a Step while it runs.
  class Seat {
   public:
    explicit Seat(CpuShare* share);
    ~Seat();
    Seat(const Seat&) = delete;
    Seat& operator=(const Seat&) = delete;
    // Threads this Step may use now (0: no limit).
    int Threads() const { return share_->ThreadsPerStep(); }

   private:
    CpuShare* share_;
  };

  int ThreadsPerStep() const;
  int cores() const { return cores_; }
  bool shared() const { return shared_; }

 private:
  int cores_;
  bool shared_;
  std::atomic<int> running_{0};
};

}  // namespace culinarycut::server
