// Frames across MPI ranks. MPI is initialised only when a launcher (mpirun, srun) started the
// process, so a plain run needs no mpirun; without one there is a single rank and no MPI call.
#pragma once

namespace sl {

class Ranks {
 public:
  Ranks();   // MPI_Init_thread (funneled: only this thread calls MPI) under a launcher
  ~Ranks();  // MPI_Finalize
  Ranks(const Ranks &) = delete;
  Ranks &operator=(const Ranks &) = delete;

  bool parallel() const { return size_ > 1; }
  int rank() const { return rank_; }
  int size() const { return size_; }
  int ranks_on_node() const { return local_size_; }
  // This rank's share of the node's cores: the cores it may run on, at most cores / ranks on node.
  int thread_share() const;

  void barrier() const;
  // A rank tells rank 0 that `frames` more of its frames are finished, `failed` of them failed,
  // after `milliseconds` of rendering.
  void report(int frames, int failed, int milliseconds) const;
  // Rank 0: one report if any arrived (non-blocking), or waits for one; false when none arrived.
  bool poll(int *frames, int *failed, int *milliseconds, bool wait) const;
  // Rank 0's values on every rank.
  void broadcast(double *values, int count) const;
  // Sums an integer over all ranks, result on every rank.
  int sum(int value) const;

 private:
  int rank_ = 0, size_ = 1, local_size_ = 1;
  bool initialised_ = false;
};

}  // namespace sl
