#include "sim/parallel/communicator.h"

#include <algorithm>
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
bool g_agreed_failure = false;  // an agreement ended in an error: every rank knows it

bool g_checks_over = false;  // a DistributedStep began: ranks depend on each other

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

// A non-blocking operation waited for napping (collectives too: a waiting
// rank left spinning in MPI_Bcast took the core from rank 0's model checks).
void wait_for(MPI_Request& request, const char* what) {
  wait_napping([&] {
    int done = 0;
    check(MPI_Test(&request, &done, MPI_STATUS_IGNORE), what);
    return done != 0;
  });
}

// MPI counts are ints: a message goes as its size, then pieces of at most
// 1 GiB (MCREF_MPI_PIECE_BYTES, for tests: smaller pieces, the same bytes).
std::size_t piece_bytes() {
  static const std::size_t bytes = [] {
    const char* v = std::getenv("MCREF_MPI_PIECE_BYTES");
    const long long b = v ? std::atoll(v) : 0;
    return b > 0 && b <= (1LL << 30) ? static_cast<std::size_t>(b) : std::size_t(1) << 30;
  }();
  return bytes;
}

// Calls op(offset, count) for each piece of a message of n bytes.
template <class Op>
void for_each_piece(std::size_t n, const Op& op) {
  for (std::size_t at = 0; at < n; at += piece_bytes()) op(at, static_cast<int>(std::min(piece_bytes(), n - at)));
}

// Rank `root`'s text on every rank.
void broadcast_from(int root, std::string& text) {
  unsigned long long n = text.size();
  MPI_Request request;
  check(MPI_Ibcast(&n, 1, MPI_UNSIGNED_LONG_LONG, root, MPI_COMM_WORLD, &request), "MPI_Ibcast");
  wait_for(request, "MPI_Ibcast");
  text.resize(n);
  for_each_piece(n, [&](std::size_t at, int count) {
    check(MPI_Ibcast(text.data() + at, count, MPI_BYTE, root, MPI_COMM_WORLD, &request), "MPI_Ibcast");
    wait_for(request, "MPI_Ibcast");
  });
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
  unsigned long long n = bytes.size();
  MPI_Request request;
  check(MPI_Isend(&n, 1, MPI_UNSIGNED_LONG_LONG, to, tag, MPI_COMM_WORLD, &request), "MPI_Isend");
  wait_for(request, "MPI_Isend");
  for_each_piece(n, [&](std::size_t at, int count) {
    check(MPI_Isend(bytes.data() + at, count, MPI_BYTE, to, tag, MPI_COMM_WORLD, &request), "MPI_Isend");
    wait_for(request, "MPI_Isend");
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
  // The size, then the pieces from the same rank (in order: MPI does not
  // let messages of one sender and tag overtake each other).
  unsigned long long n = 0;
  check(MPI_Recv(&n, 1, MPI_UNSIGNED_LONG_LONG, st.MPI_SOURCE, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE), "MPI_Recv");
  std::string bytes(static_cast<std::size_t>(n), '\0');
  for_each_piece(n, [&](std::size_t at, int count) {
    MPI_Request request;
    check(MPI_Irecv(bytes.data() + at, count, MPI_BYTE, st.MPI_SOURCE, tag, MPI_COMM_WORLD, &request), "MPI_Irecv");
    wait_for(request, "MPI_Irecv");
  });
  if (sender) *sender = st.MPI_SOURCE;
  return bytes;
}

void Communicator::broadcast(std::string& text) const {
  if (mpi_) broadcast_from(0, text);
}

MpiSession::MpiSession(int* argc, char*** argv, bool wanted) {
  if (!wanted || !launched_by_mpi()) return;
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
MpiSession::MpiSession(int*, char***, bool) { (void)launched_by_mpi; }
MpiSession::~MpiSession() = default;
void MpiSession::abort(int code) { std::exit(code); }

#endif

bool MpiSession::active() { return g_mpi; }

int MpiSession::launcher_rank() {
  for (const char* v : {"OMPI_COMM_WORLD_RANK", "PMI_RANK", "PMIX_RANK"})
    if (const char* r = std::getenv(v)) return std::atoi(r);
  return 0;
}

DistributedStep::DistributedStep() : uncaught_(std::uncaught_exceptions()) { g_checks_over = true; }
DistributedStep::~DistributedStep() {
  if (std::uncaught_exceptions() > uncaught_) g_broken = true;
}
bool DistributedStep::broken() { return g_broken; }

namespace {
// The agreement itself: the lowest failing rank, then its error from it.
std::string agreement(std::string error) {
#ifdef MCREF_WITH_MPI
  if (g_mpi && g_size > 1) {
    int mine = error.empty() ? g_size : g_rank, lowest = g_size;
    MPI_Request request;
    check(MPI_Iallreduce(&mine, &lowest, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD, &request), "MPI_Iallreduce");
    wait_for(request, "MPI_Iallreduce");
    if (lowest == g_size) return "";
    broadcast_from(lowest, error);
    g_agreed_failure = true;
    if (lowest != 0) error = "rank " + std::to_string(lowest) + " of " + std::to_string(g_size) + ": " + error;
  }
#endif
  return error;
}
}  // namespace

void agree_on_error(const Communicator& comm, std::string error) {
  if (comm.size() > 1) error = agreement(error);
  if (!error.empty()) throw ConfigError(error);
}

std::string join_agreement(const std::string& error) {
  if (!g_mpi || g_size < 2 || g_agreed_failure || g_broken || g_checks_over) return error;
  return agreement(error.empty() ? std::string("failed") : error);
}

void check_on_root(const Communicator& comm, const std::function<void()>& check) {
  check_on_every_rank(comm, comm.root() ? check : [] {});
}

void check_on_every_rank(const Communicator& comm, const std::function<void()>& check) {
  std::string error;
  try {
    check();
  } catch (const ConfigError& e) {
    if (comm.size() == 1) throw;
    error = e.what();
  }
  agree_on_error(comm, error);
}

}  // namespace mcref
