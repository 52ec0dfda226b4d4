// mcref simulate under mpirun (issue #17): the batches spread over the ranks
// and reduced on rank 0 in batch order give the bytes of one process (cmp,
// with SOURCE_DATE_EPOCH fixing the date), for every geometry kind and for
// count attributes (the sphere phase estimator's missed rays); bad input is
// one line from rank 0 and a non-zero exit on every rank, nothing written.
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
  };
  for (const Case& c : cases) {
    // The command lines are the same (stored in the file), only the directory differs.
    const std::string args = "simulate " + experiment(c.experiment) + " -o t.h5 --quiet " + c.sets;
    std::string err;
    ASSERT_EQ(shell(dir_ / "one", "SOURCE_DATE_EPOCH=1 " + mcref(args), &err), 0) << err;
    for (int n : {2, 3}) {
      fs::remove(dir_ / "ranks" / "t.h5");
      ASSERT_EQ(shell(dir_ / "ranks", "SOURCE_DATE_EPOCH=1 " + mcref_ranks(n, args), &err), 0) << err;
      EXPECT_EQ(rank_codes(dir_ / "ranks", n), std::vector<int>(static_cast<std::size_t>(n), 0));
      EXPECT_EQ(shell(dir_, "cmp one/t.h5 ranks/t.h5", nullptr), 0) << c.experiment << " on " << n << " ranks";
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
