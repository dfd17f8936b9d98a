#include "parallel/communicator.hpp"

#include <algorithm>
#include <cstdlib>

#include "core/error.hpp"

#ifdef NARWHAL_HAVE_MPI
#include <mpi.h>
#endif

namespace narwhal {

#ifdef NARWHAL_HAVE_MPI

bool built_with_mpi() { return true; }

ParallelSession::ParallelSession(int& argc, char**& argv) {
  int ready = 0;
  MPI_Initialized(&ready);
  if (!ready) MPI_Init(&argc, &argv);
}

ParallelSession::~ParallelSession() {
  int done = 0;
  MPI_Finalized(&done);
  if (!done) MPI_Finalize();
}

Communicator::Communicator() {
  int ready = 0;
  MPI_Initialized(&ready);
  if (!ready) return;  // used before MPI_Init (or without a session): one rank
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

namespace {
template <class T>
T reduce(T x, MPI_Datatype type, MPI_Op op, int size) {
  if (size == 1) return x;
  T out{};
  MPI_Allreduce(&x, &out, 1, type, op, MPI_COMM_WORLD);
  return out;
}
}  // namespace

Real Communicator::sum(Real x) const { return reduce(x, MPI_DOUBLE, MPI_SUM, size_); }
Real Communicator::max(Real x) const { return reduce(x, MPI_DOUBLE, MPI_MAX, size_); }
Real Communicator::min(Real x) const { return reduce(x, MPI_DOUBLE, MPI_MIN, size_); }
long long Communicator::sum(long long x) const { return reduce(x, MPI_LONG_LONG, MPI_SUM, size_); }

void Communicator::sum(std::vector<Real>& v) const {
  if (size_ == 1 || v.empty()) return;
  MPI_Allreduce(MPI_IN_PLACE, v.data(), static_cast<int>(v.size()), MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
}

void Communicator::broadcast(std::vector<Real>& v, int root) const {
  if (size_ == 1) return;
  long long n = static_cast<long long>(v.size());
  MPI_Bcast(&n, 1, MPI_LONG_LONG, root, MPI_COMM_WORLD);
  v.resize(static_cast<std::size_t>(n));
  if (n > 0) MPI_Bcast(v.data(), static_cast<int>(n), MPI_DOUBLE, root, MPI_COMM_WORLD);
}

void Communicator::broadcast(std::string& s, int root) const {
  if (size_ == 1) return;
  long long n = static_cast<long long>(s.size());
  MPI_Bcast(&n, 1, MPI_LONG_LONG, root, MPI_COMM_WORLD);
  s.resize(static_cast<std::size_t>(n));
  if (n > 0) MPI_Bcast(s.data(), static_cast<int>(n), MPI_CHAR, root, MPI_COMM_WORLD);
}

// Large messages go in pieces below INT_MAX bytes (MPI counts are int).
void Communicator::send(const void* data, std::size_t bytes, int to, int tag) const {
  constexpr std::size_t chunk = std::size_t{1} << 30;
  const char* p = static_cast<const char*>(data);
  for (std::size_t done = 0; done < bytes; done += chunk)
    MPI_Send(p + done, static_cast<int>(std::min(chunk, bytes - done)), MPI_BYTE, to, tag, MPI_COMM_WORLD);
}

void Communicator::receive(void* data, std::size_t bytes, int from, int tag) const {
  constexpr std::size_t chunk = std::size_t{1} << 30;
  char* p = static_cast<char*>(data);
  for (std::size_t done = 0; done < bytes; done += chunk)
    MPI_Recv(p + done, static_cast<int>(std::min(chunk, bytes - done)), MPI_BYTE, from, tag, MPI_COMM_WORLD,
             MPI_STATUS_IGNORE);
}

void Communicator::barrier() const {
  if (size_ > 1) MPI_Barrier(MPI_COMM_WORLD);
}

void Communicator::abort(int code) const {
  MPI_Abort(MPI_COMM_WORLD, code);
  std::exit(code);
}

#else  // one rank, no MPI

bool built_with_mpi() { return false; }
ParallelSession::ParallelSession(int&, char**&) {}
ParallelSession::~ParallelSession() = default;
Communicator::Communicator() = default;
Real Communicator::sum(Real x) const { return x; }
Real Communicator::max(Real x) const { return x; }
Real Communicator::min(Real x) const { return x; }
long long Communicator::sum(long long x) const { return x; }
void Communicator::sum(std::vector<Real>&) const {}
void Communicator::broadcast(std::vector<Real>&, int) const {}
void Communicator::broadcast(std::string&, int) const {}
void Communicator::send(const void*, std::size_t, int to, int) const { fail("send to rank {} without MPI", to); }
void Communicator::receive(void*, std::size_t, int from, int) const { fail("receive from rank {} without MPI", from); }
void Communicator::barrier() const {}
void Communicator::abort(int code) const { std::exit(code); }

#endif

Communicator Communicator::world() { return Communicator(); }

}  // namespace narwhal
