// The processes that share one job: the ranks of an MPI run (the program was started by mpirun,
// or by srun under Slurm), or this process alone. The offline side splits its cycles over them
// (trainer/calibrate/shared_dataset.hpp) and joins their sums here; nothing else in lptn speaks MPI.
//
// Without Open MPI in the build (LPTN_WITH_MPI=OFF) every process is alone, and a process that an
// MPI launcher started refuses to run (every rank would do the whole job and write the same file).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace lptn::hostio {

class ProcessGroup {
 public:
  // The job's processes: MPI_COMM_WORLD when an MPI launcher started this one (MPI is initialized
  // on the first call and finalized at exit), else this process alone. Throws std::runtime_error
  // when a launcher started it and this lptn has no MPI.
  static const ProcessGroup& world();
  // This process alone, whatever launched it (tests, and the commands that do not share work).
  static const ProcessGroup& alone();
  // Whether world() has joined this process to other ranks (for error paths, which must not be
  // the first to call world()).
  static bool joined();

  int rank() const { return rank_; }
  int size() const { return size_; }
  bool shared() const { return size_ > 1; }
  // Whether this process writes the job's outputs and prints its progress (rank 0).
  bool leads() const { return rank_ == 0; }

  // Every rank's `values` replaced by the element-wise sum over the ranks (MPI_Allreduce). Where
  // at most one rank contributes a non-zero to an element, the sum is that number exactly, in
  // whatever order the ranks are added: the way results stay equal to a single process's.
  void sum(double* values, std::size_t n) const;
  void sum(std::vector<double>& values) const { sum(values.data(), values.size()); }
  // Every rank's string, in rank order, on every rank (MPI_Allgatherv).
  std::vector<std::string> gather(const std::string& mine) const;
  // Bytes from this rank to rank `to`, and from `from` to this one (blocking MPI_Send / MPI_Recv;
  // the receiver learns the size). Alone there is no other rank: std::logic_error.
  void send(int to, const std::string& bytes) const;
  std::string receive(int from) const;
  // Ends every rank of the job with `code` (MPI_Abort): one rank's error must not leave the others
  // waiting in a sum forever. Alone: std::exit.
  [[noreturn]] void abort(int code) const;

 private:
  ProcessGroup(int rank, int size) : rank_(rank), size_(size) {}
  int rank_ = 0, size_ = 1;
};

// Whether an MPI launcher (mpirun, mpiexec, srun) started this process, from its environment.
bool launched_by_mpi();

}  // namespace lptn::hostio
