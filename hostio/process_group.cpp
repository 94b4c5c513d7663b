#include "hostio/process_group.hpp"

#include <cstdint>
#include <cstdlib>
#include <string>
#include <stdexcept>

#if LPTN_WITH_MPI
#include <mpi.h>
#endif

namespace lptn::hostio {
namespace {
bool joined_ranks = false;
}  // namespace

bool ProcessGroup::joined() { return joined_ranks; }

bool launched_by_mpi() {
  // Open MPI's mpirun, MPICH's and Intel's Hydra, Slurm's srun with PMI or PMIx.
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK", "PMI_RANK"})
    if (std::getenv(name) != nullptr) return true;
  return false;
}

#if LPTN_WITH_MPI
namespace {
// MPI_Finalize after main returns, once, if MPI_Init ran.
struct Finalizer {
  ~Finalizer() {
    int initialized = 0, finalized = 0;
    MPI_Initialized(&initialized);
    MPI_Finalized(&finalized);
    if (initialized && !finalized) MPI_Finalize();
  }
};
}  // namespace

const ProcessGroup& ProcessGroup::world() {
  static const ProcessGroup group = [] {
    if (!launched_by_mpi()) return ProcessGroup(0, 1);
    static Finalizer finalizer;
    int provided = 0;
    // Threads compute (parallel_for), the main thread alone calls MPI.
    MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
    int rank = 0, size = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    joined_ranks = size > 1;
    return ProcessGroup(rank, size);
  }();
  return group;
}

void ProcessGroup::sum(double* values, std::size_t n) const {
  if (!shared() || n == 0) return;
  // MPI counts are int: large buffers go in pieces.
  constexpr std::size_t kPiece = std::size_t{1} << 28;
  for (std::size_t at = 0; at < n; at += kPiece) {
    const std::size_t count = n - at < kPiece ? n - at : kPiece;
    MPI_Allreduce(MPI_IN_PLACE, values + at, static_cast<int>(count), MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  }
}

std::vector<std::string> ProcessGroup::gather(const std::string& mine) const {
  if (!shared()) return {mine};
  const int length = static_cast<int>(mine.size());
  std::vector<int> lengths(static_cast<std::size_t>(size_)), offsets(static_cast<std::size_t>(size_));
  MPI_Allgather(&length, 1, MPI_INT, lengths.data(), 1, MPI_INT, MPI_COMM_WORLD);
  int total = 0;
  for (int r = 0; r < size_; ++r) {
    offsets[static_cast<std::size_t>(r)] = total;
    total += lengths[static_cast<std::size_t>(r)];
  }
  std::string all(static_cast<std::size_t>(total), '\0');
  MPI_Allgatherv(mine.data(), length, MPI_CHAR, all.data(), lengths.data(), offsets.data(), MPI_CHAR, MPI_COMM_WORLD);
  std::vector<std::string> out;
  for (int r = 0; r < size_; ++r)
    out.push_back(all.substr(static_cast<std::size_t>(offsets[static_cast<std::size_t>(r)]),
                             static_cast<std::size_t>(lengths[static_cast<std::size_t>(r)])));
  return out;
}

void ProcessGroup::send(int to, const std::string& bytes) const {
  if (!shared() || to == rank_ || to < 0 || to >= size_) throw std::logic_error("ProcessGroup::send: no rank " + std::to_string(to));
  if (bytes.size() > static_cast<std::size_t>(INT32_MAX)) throw std::length_error("ProcessGroup::send: over 2 GB");
  MPI_Send(bytes.data(), static_cast<int>(bytes.size()), MPI_CHAR, to, 0, MPI_COMM_WORLD);
}

std::string ProcessGroup::receive(int from) const {
  if (!shared() || from == rank_ || from < 0 || from >= size_)
    throw std::logic_error("ProcessGroup::receive: no rank " + std::to_string(from));
  MPI_Status status;
  MPI_Probe(from, 0, MPI_COMM_WORLD, &status);
  int count = 0;
  MPI_Get_count(&status, MPI_CHAR, &count);
  std::string bytes(static_cast<std::size_t>(count), '\0');
  MPI_Recv(bytes.data(), count, MPI_CHAR, from, 0, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  return bytes;
}

void ProcessGroup::abort(int code) const {
  if (shared()) MPI_Abort(MPI_COMM_WORLD, code);
  std::exit(code);
}

#else

const ProcessGroup& ProcessGroup::world() {
  if (launched_by_mpi())
    throw std::runtime_error(
        "an MPI launcher started this process, but this lptn was built without Open MPI (LPTN_WITH_MPI=OFF): "
        "every rank would do the whole job; run it without mpirun, or build with libopenmpi-dev installed");
  return alone();
}

void ProcessGroup::sum(double*, std::size_t) const {}

std::vector<std::string> ProcessGroup::gather(const std::string& mine) const { return {mine}; }

void ProcessGroup::send(int to, const std::string&) const {
  throw std::logic_error("ProcessGroup::send: no rank " + std::to_string(to) + " (built without MPI)");
}

std::string ProcessGroup::receive(int from) const {
  throw std::logic_error("ProcessGroup::receive: no rank " + std::to_string(from) + " (built without MPI)");
}

void ProcessGroup::abort(int code) const { std::exit(code); }

#endif

const ProcessGroup& ProcessGroup::alone() {
  static const ProcessGroup group(0, 1);
  return group;
}

}  // namespace lptn::hostio
