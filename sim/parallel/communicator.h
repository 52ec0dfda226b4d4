#pragma once
// The ranks mcref runs on: under mpirun (or srun) in an MPI build, the MPI
// world; run plainly, or without MPI, one process (MPI is not even
// initialised, so there is no MPI output). Only the main thread of a rank
// talks to the others (MPI_THREAD_FUNNELED).
//
// Errors: every rank checks its input before the ranks depend on each other,
// and the checks end in agreements (agree_on_error, check_on_root) where every
// rank gives its own error, if any: a rank that failed its checks alone (a
// file its node cannot see, a node's memory budget) joins the next agreement
// from main's error path (join_agreement), so no rank is left waiting; every
// rank then exits with the error of the lowest failing rank, printed once by
// rank 0. An error inside a DistributedStep (a rank alone, while the others
// wait for it) ends the whole job (MPI_Abort).
#include <functional>
#include <string>

namespace mcref {

class Communicator {
 public:
  static constexpr int kAnyRank = -1;

  // This process alone.
  static const Communicator& self();
  // Every rank of the job (self() when not launched by an MPI launcher).
  static const Communicator& world();

  int rank() const { return rank_; }
  int size() const { return size_; }
  bool root() const { return rank_ == 0; }

  // Point to point; `tag` keeps message kinds apart. Returns once `bytes`
  // may be reused; the sending rank sleeps while the receiver is not ready.
  // Any size: sent as its size, then pieces of at most 1 GiB (MPI counts are
  // int; MCREF_MPI_PIECE_BYTES sets smaller pieces, for tests).
  void send(int to, int tag, const std::string& bytes) const;
  // Waits for a message from `from` (or kAnyRank) with `tag`; the waiting rank
  // sleeps between polls, so it leaves its core to the threads that compute.
  std::string receive(int from, int tag, int* sender = nullptr) const;
  // A message from `from` with `tag` is waiting (does not wait).
  bool pending(int from, int tag) const;
  // Rank 0's `text` on every rank.
  void broadcast(std::string& text) const;

 private:
  Communicator(int rank, int size, bool mpi) : rank_(rank), size_(size), mpi_(mpi) {}
  int rank_ = 0, size_ = 1;
  bool mpi_ = false;
  friend class MpiSession;
};

// Initialises MPI for the life of main() when launched by an MPI launcher
// (OMPI_COMM_WORLD_SIZE, PMI_SIZE or PMIX_RANK set) in an MPI build, if
// `wanted` (the verbs that spread work over ranks: a process that does not
// start MPI may run mcref again within the same task).
class MpiSession {
 public:
  MpiSession(int* argc, char*** argv, bool wanted = true);
  // This process's rank as its launcher set it (0 if not launched by one),
  // known without initialising MPI.
  static int launcher_rank();
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
  // Ends every rank of the job now (an error a rank met on its own).
  [[noreturn]] static void abort(int code);
  static bool active();
};

// Marks the span in which ranks wait for each other: an exception leaving
// it on one rank must end the job (main asks DistributedStep::broken()).
class DistributedStep {
 public:
  // Also ends the checks: from here on, main's error path joins no agreement.
  DistributedStep();
  ~DistributedStep();
  DistributedStep(const DistributedStep&) = delete;
  DistributedStep& operator=(const DistributedStep&) = delete;
  // An exception left a DistributedStep on this rank.
  static bool broken();

 private:
  int uncaught_;
};

// An agreement: every rank gives its `error` ("" if none); if any is not
// empty, throws on every rank the ConfigError of the lowest rank that gave one
// (from a rank other than 0, prefixed "rank K of N: ").
void agree_on_error(const Communicator& comm, std::string error);

// For main's error path: if the world has more than one rank, no agreement
// has failed yet and no DistributedStep has begun, the other ranks may be
// waiting in an agreement for this one: joins it with `error`.
// Returns the error every rank agreed on (this one's, or a lower rank's).
std::string join_agreement(const std::string& error);

// Runs `check` on rank 0 alone (e.g. the output path checks: only rank 0
// writes there) and throws its ConfigError on every rank.
void check_on_root(const Communicator& comm, const std::function<void()>& check);

// Runs `check` on every rank (e.g. each node's memory budget) and throws the
// lowest failing rank's ConfigError on every rank.
void check_on_every_rank(const Communicator& comm, const std::function<void()>& check);

}  // namespace mcref
