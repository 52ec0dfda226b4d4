#pragma once
// Running the mcref binary under mpirun from a test (MPI builds only): the
// flags OpenMPI needs in CI (root, more ranks than cores), a quiet mpirun (no
// banners of its own), and each rank's exit code.
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace mcref_test {

inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// Runs a shell command in `dir`; returns its exit code, stderr in *err.
inline int shell(const std::filesystem::path& dir, const std::string& cmd, std::string* err) {
  const std::string full = "cd '" + dir.string() + "' && " + cmd + " 2> err.txt";
  const int status = std::system(full.c_str());
  if (err) *err = slurp(dir / "err.txt");
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// mpirun -np N with the flags CI needs.
inline std::string mpirun(int ranks) {
  return std::string("'") + MCREF_MPIEXEC + "' -q --allow-run-as-root --oversubscribe -np " + std::to_string(ranks) + " ";
}

// `mcref args` on N ranks; each rank writes its exit code to rc.<rank> (and exits with it).
inline std::string mcref_ranks(int ranks, const std::string& args) {
  return mpirun(ranks) + "sh -c '\"" + std::string(MCREF_BINARY) + "\" " + args +
         "; rc=$?; echo $rc > rc.$OMPI_COMM_WORLD_RANK; exit $rc'";
}

// `mcref args` on N ranks for a failing run: each rank writes its exit code to
// rc.<rank> (stale ones removed first), then exits 0. (mpirun ends the job as
// soon as one rank exits non-zero, which can kill another rank's shell before
// it has written its code: a race under load.) Check the codes with rank_codes().
inline std::string mcref_ranks_failing(int ranks, const std::string& args) {
  return "rm -f rc.*; " + mpirun(ranks) + "sh -c '\"" + std::string(MCREF_BINARY) + "\" " + args +
         "; echo $? > rc.$OMPI_COMM_WORLD_RANK'";
}

// `mcref args` on N ranks; each rank writes its pid to pid.<rank> (the shell
// execs mcref, so it is mcref's pid).
inline std::string mcref_ranks_pids(int ranks, const std::string& args) {
  return mpirun(ranks) + "sh -c 'echo $$ > pid.$OMPI_COMM_WORLD_RANK; exec \"" + std::string(MCREF_BINARY) + "\" " + args + "'";
}

// Exit codes the ranks of mcref_ranks() wrote, in rank order.
inline std::vector<int> rank_codes(const std::filesystem::path& dir, int ranks) {
  std::vector<int> codes;
  for (int r = 0; r < ranks; ++r) {
    std::ifstream in(dir / ("rc." + std::to_string(r)));
    int c = -1;
    in >> c;
    codes.push_back(c);
  }
  return codes;
}

inline std::string mcref(const std::string& args) { return std::string("'") + MCREF_BINARY + "' " + args; }

}  // namespace mcref_test
