#include "sim/parallel/communicator.h"

#include <chrono>
#include <cstdlib>
#include <exception>
#include <stdexcept>
#include <thread>

#include "sim/experiment/config_error.h"

#ifdef MCREF_WITH_MPI
#define OMPI_SKIP_MPICXX 1  // the C API only
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>
#endif

namespace mcref {

namespace {

bool g_mpi = false;  // MPI initialised by MpiSession
int g_rank = 0, g_size = 1;
bool g_broken = false;  // an exception left a DistributedStep

bool launched_by_mpi() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
    if (std::getenv(v)) return true;
  return false;
}

[[noreturn]] void no_mpi() { throw std::logic_error("mcref: message passing on a single-process communicator"); }

#ifdef MCREF_WITH_MPI
void check(int rc, const char* what) {
  if (rc != MPI_SUCCESS) throw std::runtime_error(std::string("MPI error in ") + what);
}

// Polls `done` with naps of 50 us doubling to 2 ms between polls: a blocking
// MPI call would spin on the core while the other rank is busy, taking it
// from the threads that compute.
template <class Done>
void wait_napping(const Done& done) {
  for (auto nap = std::chrono::microseconds(50); !done();) {
    std::this_thread::sleep_for(nap);
    if (nap < std::chrono::milliseconds(2)) nap *= 2;
  }
}
#endif

}  // namespace

const Communicator& Communicator::self() {
  static const Communicator c(0, 1, false);
  return c;
}

const Communicator& Communicator::world() {
  static const Communicator c(g_rank, g_size, g_mpi && g_size > 1);
  return g_mpi && g_size > 1 ? c : self();
}

#ifdef MCREF_WITH_MPI

void Communicator::send(int to, int tag, const std::string& bytes) const {
  if (!mpi_) no_mpi();
  // A large message waits for the receiver to be ready: sleep meanwhile.
  MPI_Request request;
  check(MPI_Isend(bytes.data(), static_cast<int>(bytes.size()), MPI_BYTE, to, tag, MPI_COMM_WORLD, &request), "MPI_Isend");
  wait_napping([&] {
    int sent = 0;
    check(MPI_Test(&request, &sent, MPI_STATUS_IGNORE), "MPI_Test");
    return sent != 0;
  });
}

bool Communicator::pending(int from, int tag) const {
  if (!mpi_) no_mpi();
  int flag = 0;
  MPI_Status st;
  check(MPI_Iprobe(from == kAnyRank ? MPI_ANY_SOURCE : from, tag, MPI_COMM_WORLD, &flag, &st), "MPI_Iprobe");
  return flag != 0;
}

std::string Communicator::receive(int from, int tag, int* sender) const {
  if (!mpi_) no_mpi();
  MPI_Status st;
  wait_napping([&] {
    int flag = 0;
    check(MPI_Iprobe(from == kAnyRank ? MPI_ANY_SOURCE : from, tag, MPI_COMM_WORLD, &flag, &st), "MPI_Iprobe");
    return flag != 0;
  });
  int count = 0;
  check(MPI_Get_count(&st, MPI_BYTE, &count), "MPI_Get_count");
  std::string bytes(static_cast<std::size_t>(count), '\0');
  check(MPI_Recv(bytes.data(), count, MPI_BYTE, st.MPI_SOURCE, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE), "MPI_Recv");
  if (sender) *sender = st.MPI_SOURCE;
  return bytes;
}

void Communicator::broadcast(std::string& text) const {
  if (!mpi_) return;
  unsigned long long n = text.size();
  check(MPI_Bcast(&n, 1, MPI_UNSIGNED_LONG_LONG, 0, MPI_COMM_WORLD), "MPI_Bcast");
  text.resize(n);
  check(MPI_Bcast(text.data(), static_cast<int>(n), MPI_BYTE, 0, MPI_COMM_WORLD), "MPI_Bcast");
}

MpiSession::MpiSession(int* argc, char*** argv) {
  if (!launched_by_mpi()) return;
  int provided = 0;
  MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
  MPI_Comm_rank(MPI_COMM_WORLD, &g_rank);
  MPI_Comm_size(MPI_COMM_WORLD, &g_size);
  g_mpi = true;
}

MpiSession::~MpiSession() {
  if (g_mpi) MPI_Finalize();
}

void MpiSession::abort(int code) {
  if (g_mpi) MPI_Abort(MPI_COMM_WORLD, code);
  std::exit(code);
}

#else  // one process

void Communicator::send(int, int, const std::string&) const { no_mpi(); }
bool Communicator::pending(int, int) const { no_mpi(); }
std::string Communicator::receive(int, int, int*) const { no_mpi(); }
void Communicator::broadcast(std::string&) const {}
MpiSession::MpiSession(int*, char***) { (void)launched_by_mpi; }
MpiSession::~MpiSession() = default;
void MpiSession::abort(int code) { std::exit(code); }

#endif

bool MpiSession::active() { return g_mpi; }

DistributedStep::DistributedStep() : uncaught_(std::uncaught_exceptions()) {}
DistributedStep::~DistributedStep() {
  if (std::uncaught_exceptions() > uncaught_) g_broken = true;
}
bool DistributedStep::broken() { return g_broken; }

void agree_on_error(const Communicator& comm, std::string error) {
  comm.broadcast(error);
  if (!error.empty()) throw ConfigError(error);
}

void check_on_root(const Communicator& comm, const std::function<void()>& check) {
  std::string error;
  if (comm.root()) {
    try {
      check();
    } catch (const ConfigError& e) {
      if (comm.size() == 1) throw;
      error = e.what();
    }
  }
  agree_on_error(comm, error);
}

}  // namespace mcref
