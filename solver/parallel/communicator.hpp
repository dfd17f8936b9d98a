#pragma once
// The ranks a run is distributed over (issue #6): OpenMPI's world communicator when
// built with NARWHAL_MPI, otherwise a one-rank stand-in with the same interface, so
// that the solver has one code path and the serial build needs no MPI at all.
//
// Usage:
//   int main(int argc, char** argv) {
//     narwhal::ParallelSession session(argc, argv);   // MPI_Init / MPI_Finalize
//     const auto comm = narwhal::Communicator::world();
//     const double total = comm.sum(local);            // the same on every rank
//   }
// Reductions are deterministic for a given rank count (MPI_Allreduce's order is fixed
// per communicator size in OpenMPI's default algorithms; vectors reduce element-wise).
//
// Only the top of a run (main, the run's driver) asks for world(). Everything below
// that communicates takes the communicator as an argument or holds the one it was
// built with, and its comment says "collective over comm": every rank must call it,
// so a call inside a branch that only some ranks take would hang.
#include <cstddef>
#include <string>
#include <vector>

#include "core/types.hpp"

namespace narwhal {

class ParallelSession {
 public:
  ParallelSession(int& argc, char**& argv);
  ~ParallelSession();
  ParallelSession(const ParallelSession&) = delete;
  ParallelSession& operator=(const ParallelSession&) = delete;
};

class Communicator {
 public:
  // The world communicator (queried afresh: valid after ParallelSession's MPI_Init).
  static Communicator world();

  int rank() const { return rank_; }
  int size() const { return size_; }
  bool is_root() const { return rank_ == 0; }

  Real sum(Real x) const;
  Real max(Real x) const;
  Real min(Real x) const;
  long long sum(long long x) const;
  void sum(std::vector<Real>& v) const;  // element-wise, in place
  void broadcast(std::vector<Real>& v, int root = 0) const;
  void broadcast(std::string& s, int root = 0) const;
  // Point to point, blocking (gathers to the writing rank); `bytes` must match.
  void send(const void* data, std::size_t bytes, int to, int tag) const;
  void receive(void* data, std::size_t bytes, int from, int tag) const;
  void barrier() const;
  [[noreturn]] void abort(int code) const;  // ends every rank of the job

 private:
  Communicator();
  int rank_ = 0, size_ = 1;
};

// True when this build distributes over MPI ranks.
bool built_with_mpi();

}  // namespace narwhal
