// mcref simulate under mpirun (issue #17): the batches spread over the ranks
// and reduced on rank 0 in batch order give the bytes of one process (cmp,
// with SOURCE_DATE_EPOCH fixing the date), for every geometry kind and slab walk, and for
// count attributes (the sphere phase estimator's missed rays); bad input is
// one line from rank 0 and a non-zero exit on every rank, nothing written.
#include <algorithm>
#include <gtest/gtest.h>
#include <unistd.h>

#include "tests/sim/parallel/mpi_cli.h"

namespace fs = std::filesystem;
using namespace mcref_test;

namespace {

class SimulateMpi : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("mcref_test_simulate_mpi_" + std::to_string(getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "one");
    fs::create_directories(dir_ / "ranks");
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

std::string experiment(const std::string& name) {
  return std::string("'") + MCREF_SOURCE_DIR + "/validate/experiments/" + name + ".toml'";
}

}  // namespace

TEST_F(SimulateMpi, RanksGiveTheBytesOfOneProcess) {
  struct Case {
    const char* experiment;
    const char* sets;
  };
  // 5 batches: over 2 and 3 ranks, rank 0 gets more batches than the others.
  const Case cases[] = {
      {"slab_single_layer", "--set run.batches=5 --set measure.0.samples=300"},
      {"spheres_phase", "--set run.batches=5"},
      {"micrograin_brdf_diffuse", "--set run.batches=5 --set measure.0.samples=300"},
      // The slab's other walks: the data-parallel one, next-event estimation, the
      // OpenVDB depth profile (scalar and wave).
      {"slab_single_layer", "--set run.batches=5 --set measure.0.samples=300 --set geometry.walk=wave"},
      {"slab_single_layer", "--set run.batches=5 --set measure.0.samples=300 --set geometry.estimator=next_event_mis"},
      {"slab_openvdb_profile", "--set run.batches=5 --set measure.0.samples=300"},
      {"slab_openvdb_profile", "--set run.batches=5 --set measure.0.samples=300 --set geometry.walk=wave"},
  };
  for (const Case& c : cases) {
    // The command lines are the same (stored in the file), only the directory differs.
    const std::string args = "simulate " + experiment(c.experiment) + " -o t.h5 --quiet " + c.sets;
    std::string err;
    ASSERT_EQ(shell(dir_ / "one", "SOURCE_DATE_EPOCH=1 " + mcref(args), &err), 0) << err;
    for (int n : {2, 3}) {
      fs::remove(dir_ / "ranks" / "t.h5");
      // On 3 ranks the messages go in pieces of 4 kB (1 GiB in use: MPI counts are int).
      const std::string pieces = n == 3 ? "MCREF_MPI_PIECE_BYTES=4096 " : "";
      ASSERT_EQ(shell(dir_ / "ranks", "SOURCE_DATE_EPOCH=1 " + pieces + mcref_ranks(n, args), &err), 0) << err;
      EXPECT_EQ(rank_codes(dir_ / "ranks", n), std::vector<int>(static_cast<std::size_t>(n), 0));
      EXPECT_EQ(shell(dir_, "cmp one/t.h5 ranks/t.h5", nullptr), 0) << c.experiment << " " << c.sets << " on " << n << " ranks";
    }
  }
}

TEST_F(SimulateMpi, BadInputIsOneLineFromRankZeroAndFailsEveryRank) {
  std::string err;
  shell(dir_, mcref_ranks_failing(2, "simulate " + experiment("slab_single_layer") +
                                           " -o bad.h5 --set run.batches=1"), &err);
  EXPECT_EQ(rank_codes(dir_, 2), (std::vector<int>{2, 2}));
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  EXPECT_NE(err.find("run.batches"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(dir_ / "bad.h5"));
  shell(dir_, mcref_ranks_failing(2, "simulate " + experiment("slab_single_layer") + " -o no/such/dir/t.h5"), &err);
  EXPECT_EQ(rank_codes(dir_, 2), (std::vector<int>{2, 2}));
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  EXPECT_NE(err.find("no/such/dir/t.h5: key '-o': the output's directory"), std::string::npos) << err;
}

// A rank that fails its checks alone (here rank 1, whose directory lacks the
// experiment, as a node that cannot see an input) joins the ranks' agreement:
// every rank exits 2 and rank 0 prints that rank's error, naming it. Before,
// rank 0 waited for rank 1 forever and nothing was printed (timeout 120 s here).
TEST_F(SimulateMpi, ARankFailingItsChecksAloneIsNamedAndNoRankWaits) {
  fs::create_directories(dir_ / "r0");
  fs::create_directories(dir_ / "r1");
  fs::copy_file(std::string(MCREF_SOURCE_DIR) + "/validate/experiments/slab_single_layer.toml", dir_ / "r0" / "e.toml");
  std::string err;
  const int code = shell(dir_, "rm -f rc.*; timeout 120 " + mpirun(2) + "sh -c 'cd r$OMPI_COMM_WORLD_RANK && \"" +
                                   MCREF_BINARY + "\" simulate e.toml -o ../t.h5 --set run.batches=4; echo $? > ../rc.$OMPI_COMM_WORLD_RANK'",
                         &err);
  EXPECT_NE(code, 124) << "the job hung";
  EXPECT_EQ(rank_codes(dir_, 2), (std::vector<int>{2, 2}));
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  EXPECT_NE(err.find("mcref: error: rank 1 of 2: e.toml"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(dir_ / "t.h5"));
}

// Under mpirun every rank's stdout is a terminal, even when the job's output
// goes to a file: the progress is a log there (a plain line a minute), so a
// short run writes no progress at all, only its summary; no \r redraws and no
// escape codes (they were written to the file).
// Every rank must simulate rank 0's experiment and fit its own node's memory
// budget: a rank whose copy of the file differs (here a substrate albedo of
// 0.1 against 0.6: its batches were added to rank 0's tables, exit 0, and the
// file's config said 0.6), or whose budget is too small (only rank 0's was
// checked), is named and every rank exits 2.
TEST_F(SimulateMpi, EveryRankChecksItsExperimentAndItsMemory) {
  const std::string source = std::string(MCREF_SOURCE_DIR) + "/validate/experiments/slab_single_layer.toml";
  struct Case {
    std::string setup, env1, expected;
  };
  const std::vector<Case> cases{
      {"sed 's/^seed = .*/seed = 12345/' r0/e.toml > r1/e.toml", "", "differs from rank 0's copy"},
      {"cp r0/e.toml r1/e.toml", "if [ $OMPI_COMM_WORLD_RANK = 1 ]; then export MCREF_MEMORY_LIMIT=1K; fi; ", "budget of 1 KB"},
  };
  for (const Case& c : cases) {
    fs::remove_all(dir_ / "r0");
    fs::remove_all(dir_ / "r1");
    fs::create_directories(dir_ / "r0");
    fs::create_directories(dir_ / "r1");
    fs::copy_file(source, dir_ / "r0" / "e.toml");
    ASSERT_EQ(shell(dir_, c.setup, nullptr), 0);
    std::string err;
    const int code = shell(dir_, "rm -f rc.*; timeout 120 " + mpirun(2) + "sh -c 'cd r$OMPI_COMM_WORLD_RANK && " + c.env1 + "\"" + MCREF_BINARY +
                                     "\" simulate e.toml -o ../t.h5 --set run.batches=4; echo $? > ../rc.$OMPI_COMM_WORLD_RANK'",
                           &err);
    EXPECT_NE(code, 124) << "the job hung";
    EXPECT_EQ(rank_codes(dir_, 2), (std::vector<int>{2, 2})) << c.expected << ": " << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
    EXPECT_NE(err.find("mcref: error: rank 1 of 2: "), std::string::npos) << err;
    EXPECT_NE(err.find(c.expected), std::string::npos) << err;
    EXPECT_FALSE(fs::exists(dir_ / "t.h5"));
  }
}

TEST_F(SimulateMpi, ProgressUnderMpirunIsALogNotARedrawnLine) {
  std::string err;
  ASSERT_EQ(shell(dir_, "env -u CI " + mcref_ranks(2, "simulate " + experiment("slab_single_layer") +
                                                          " -o t.h5 --set run.batches=4 --set measure.0.samples=300"),
                  &err),
            0)
      << err;
  EXPECT_EQ(err.find('\r'), std::string::npos) << err;
  EXPECT_EQ(err.find('\033'), std::string::npos) << err;
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << "the summary alone:\n" << err;
}

// The single-process verbs run on rank 0 alone and do not start MPI: under
// mpirun, `info` prints once per call, and a task may call mcref twice (the
// second call was an MPI_Init_thread error, exit 1; info printed once per rank).
TEST_F(SimulateMpi, SingleProcessVerbsRunOnRankZeroAloneAndTwice) {
  std::string err;
  ASSERT_EQ(shell(dir_, mcref("simulate " + experiment("slab_single_layer") +
                              " -o t.h5 --quiet --set run.batches=2 --set measure.0.samples=100"),
                  &err),
            0)
      << err;
  const std::string info = "\"" + std::string(MCREF_BINARY) + "\" info t.h5";
  ASSERT_EQ(shell(dir_, mpirun(3) + "sh -c '" + info + " && " + info + "' > out.txt", &err), 0) << err;
  const std::string out = slurp(dir_ / "out.txt");
  std::size_t reports = 0;
  for (std::size_t at = out.find("simulation fingerprint"); at != std::string::npos;
       at = out.find("simulation fingerprint", at + 1))
    ++reports;
  EXPECT_EQ(reports, 2u) << out;
  EXPECT_EQ(err, "");
}
