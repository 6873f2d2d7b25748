#include "ranks.h"

#include <mpi.h>
#include <sched.h>

#include <algorithm>
#include <cstdlib>
#include <thread>

namespace sl {

namespace {

constexpr int kReportTag = 9017;

// Launchers say so in the environment: Open MPI's mpirun, MPICH/Hydra and Slurm's PMI/PMIx.
bool launched_by_mpi()
{
  for (const char *v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK", "PMI_RANK"})
    if (std::getenv(v)) return true;
  return false;
}

}  // namespace

Ranks::Ranks()
{
  if (!launched_by_mpi()) return;
  int provided = 0;
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  initialised_ = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
  MPI_Comm node;
  MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &node);
  MPI_Comm_size(node, &local_size_);
  MPI_Comm_free(&node);
}

Ranks::~Ranks()
{
  if (initialised_) MPI_Finalize();
}

int Ranks::thread_share() const
{
  // A launcher that binds each rank to cores (Open MPI's default) leaves fewer cores in the mask.
  cpu_set_t mask;
  int allowed = (int)std::thread::hardware_concurrency();
  if (sched_getaffinity(0, sizeof mask, &mask) == 0) allowed = CPU_COUNT(&mask);
  const int node = std::max(1, (int)std::thread::hardware_concurrency() / std::max(1, local_size_));
  return std::max(1, std::min(allowed, node));
}

void Ranks::barrier() const
{
  if (initialised_) MPI_Barrier(MPI_COMM_WORLD);
}

void Ranks::report(int frames, int failed, int milliseconds) const
{
  if (!initialised_ || rank_ == 0) return;
  const int msg[3] = {frames, failed, milliseconds};
  MPI_Send(msg, 3, MPI_INT, 0, kReportTag, MPI_COMM_WORLD);
}

bool Ranks::poll(int *frames, int *failed, int *milliseconds, bool wait) const
{
  if (!initialised_ || rank_ != 0) return false;
  int flag = 1;
  MPI_Status st;
  if (!wait) MPI_Iprobe(MPI_ANY_SOURCE, kReportTag, MPI_COMM_WORLD, &flag, &st);
  if (!flag) return false;
  int msg[3];
  MPI_Recv(msg, 3, MPI_INT, MPI_ANY_SOURCE, kReportTag, MPI_COMM_WORLD, &st);
  *frames = msg[0];
  *failed = msg[1];
  *milliseconds = msg[2];
  return true;
}

void Ranks::broadcast(double *values, int count) const
{
  if (initialised_) MPI_Bcast(values, count, MPI_DOUBLE, 0, MPI_COMM_WORLD);
}

int Ranks::sum(int value) const
{
  if (!initialised_) return value;
  int total = 0;
  MPI_Allreduce(&value, &total, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
  return total;
}

}  // namespace sl
