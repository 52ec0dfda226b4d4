// mcref validate under mpirun (issue #17): each case's batches spread over the
// ranks give the tables and results of one process (cmp, with
// SOURCE_DATE_EPOCH fixing the date); bad input (the suite, a case's
// experiment, the output directory) is one line from rank 0, a non-zero exit
// on every rank and of mpirun, and nothing written.
#include <gtest/gtest.h>
#include <unistd.h>

#include "tests/sim/parallel/mpi_cli.h"

namespace fs = std::filesystem;
using namespace mcref_test;

namespace {

// Two cases of one slab experiment, 3 batches each (rank 0 gets 2 of them on 2 ranks).
std::string suite(const std::string& significance, const std::string& samples) {
  return "[suite]\nname = \"s\"\nsignificance = " + significance +
         "\n"
         "[[case]]\nname = \"a\"\nexperiment = \"" MCREF_SOURCE_DIR "/validate/experiments/slab_single_layer.toml\"\n"
         "set = [\"run.batches=3\", \"measure.0.samples=" + samples + "\"]\n"
         "[[case]]\nname = \"b\"\nexperiment = \"" MCREF_SOURCE_DIR "/validate/experiments/slab_single_layer.toml\"\n"
         "set = [\"run.batches=3\", \"measure.0.samples=300\", \"geometry.layer.0.alpha=0.2\"]\n";
}

class ValidateMpi : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("mcref_test_validate_mpi_" + std::to_string(getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  // A bad run on 2 ranks: every rank exits 2, mpirun exits non-zero, the one
  // line of stderr starts with `start` and holds `piece`, and OUTDIR `out` is not created.
  void expect_bad(const std::string& args, const std::string& out, const std::string& start, const std::string& piece) {
    std::string err;
    shell(dir_, mcref_ranks_failing(2, args), &err);
    EXPECT_EQ(rank_codes(dir_, 2), (std::vector<int>{2, 2})) << args;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
    EXPECT_EQ(err.rfind(start, 0), 0u) << err;
    EXPECT_NE(err.find(piece), std::string::npos) << err;
    EXPECT_NE(shell(dir_, mpirun(2) + mcref(args), &err), 0) << "mpirun exited 0 for " << args;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
    EXPECT_FALSE(fs::exists(dir_ / out)) << args;
  }
  fs::path dir_;
};

}  // namespace

TEST_F(ValidateMpi, RanksGiveTheTablesAndResultsOfOneProcess) {
  // The same command line in two directories (it is stored in the tables).
  for (const char* sub : {"one", "ranks"}) {
    fs::create_directories(dir_ / sub);
    std::ofstream(dir_ / sub / "suite.toml") << suite("0.001", "300");
  }
  const std::string args = "validate suite.toml -o out --quiet --threads 1";
  std::string err;
  // Exit 0 or 1 (a check may fail on so few paths); the same on both sides.
  const int one = shell(dir_ / "one", "SOURCE_DATE_EPOCH=1 " + mcref(args), &err);
  ASSERT_TRUE(one == 0 || one == 1) << err;
  ASSERT_EQ(shell(dir_ / "ranks", "SOURCE_DATE_EPOCH=1 " + mpirun(2) + mcref(args), &err), one) << err;
  for (const char* file : {"out/tables/a.h5", "out/tables/b.h5", "out/results.json"})
    EXPECT_EQ(shell(dir_, std::string("cmp one/") + file + " ranks/" + file, nullptr), 0) << file << " differs on 2 ranks";
}

TEST_F(ValidateMpi, BadInputIsOneLineFromRankZeroAndFailsEveryRank) {
  // The suite itself: a key out of range.
  std::ofstream(dir_ / "bad_suite.toml") << suite("0.9", "300");
  expect_bad("validate bad_suite.toml -o out", "out", "mcref: error: bad_suite.toml: key 'suite.significance'",
             "suite.significance");
  // A case's experiment: a value out of range, found before any case is simulated.
  std::ofstream(dir_ / "bad_case.toml") << suite("0.001", "-5");
  expect_bad("validate bad_case.toml -o out", "out", "mcref: error: ", "measure.0.samples");
  // The output directory: its parent is missing (checked by rank 0 alone).
  std::ofstream(dir_ / "suite.toml") << suite("0.001", "300");
  expect_bad("validate suite.toml -o no/such/out", "no", "mcref: error: no/such/out: key '-o'", "-o");
}

// Each rank checks the memory the suite's tables need against its own node's
// budget: a rank whose budget is too small (here rank 1, MCREF_MEMORY_LIMIT=1K)
// fails alone, joins the ranks' agreement, and every rank exits 2 with its error,
// named by rank. Before, the job hung with nothing printed (timeout 120 s here).
TEST_F(ValidateMpi, ARankOverItsOwnMemoryBudgetIsNamedAndNoRankWaits) {
  std::ofstream(dir_ / "suite.toml") << suite("0.001", "300");
  const auto rank = [](const std::string& limit) {
    return "-np 1 -x MCREF_MEMORY_LIMIT=" + limit + " sh -c '\"" + std::string(MCREF_BINARY) +
           "\" validate suite.toml -o out --quiet; echo $? > rc.$OMPI_COMM_WORLD_RANK'";
  };
  std::string err;
  const int code = shell(dir_, "rm -f rc.*; timeout 120 '" + std::string(MCREF_MPIEXEC) +
                                   "' -q --allow-run-as-root --oversubscribe " + rank("1T") + " : " + rank("1K"),
                         &err);
  EXPECT_NE(code, 124) << "the job hung";
  EXPECT_EQ(rank_codes(dir_, 2), (std::vector<int>{2, 2}));
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  EXPECT_NE(err.find("mcref: error: rank 1 of 2: "), std::string::npos) << err;
  EXPECT_NE(err.find("MCREF_MEMORY_LIMIT"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(dir_ / "out" / "results.json"));
}
