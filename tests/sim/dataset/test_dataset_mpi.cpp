// mcref dataset under mpirun (issue #17): the entries spread dynamically over
// the ranks give the same bytes as one process for any rank count; a job
// stopped early, or one that loses a rank (SIGKILL) mid-run, resumes from the
// finished parts with another rank count, byte-identical; bad input is one
// line from rank 0 and a non-zero exit on every rank, with nothing written.
// Rank 0 assembles the output while entries are computed; killed, it too
// leaves parts the next job resumes from.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <thread>

#include "tests/sim/parallel/mpi_cli.h"

namespace fs = std::filesystem;
using namespace mcref_test;

namespace {

const char* kBase = R"(
[geometry]
kind = "slab"

[[geometry.layer]]
phase = "sggx_surface"
alpha = 0.5
thickness = 1.0
density = 1.0
albedo = 0.8

[[geometry.layer]]
phase = "isotropic"
thickness = 1.0
density = 1.0
albedo = 0.5

[run]
seed = 1
batches = 2

[[measure]]
quantity = "brdf"
theta_i_deg = [20, 60]
theta_o_bins = 3
phi_bins = 2
samples = SAMPLES
)";

const char* kDataset = R"(
[dataset]
experiment = "base.toml"
entries = ENTRIES
seed = 7

[[parameter]]
key = "geometry.layer.count"
values = [1, 2]

[[parameter]]
key = "geometry.layer.0.thickness"
range = [0.1, 10.0]
distribution = "log_uniform"
)";

std::string with(std::string text, const std::string& key, const std::string& value) {
  return text.replace(text.find(key), key.size(), value);
}

class DatasetMpi : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("mcref_test_dataset_mpi_" + std::to_string(getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  // A dataset of 2 x per_point entries of `samples` paths per direction and batch.
  void write(int samples, int per_point) {
    std::ofstream(dir_ / "base.toml") << with(kBase, "SAMPLES", std::to_string(samples));
    std::ofstream(dir_ / "ds.toml") << with(kDataset, "ENTRIES", std::to_string(per_point));
  }
  int parts(const std::string& out) const {
    int n = 0;
    if (fs::is_directory(dir_ / (out + ".parts")))
      for (const auto& f : fs::directory_iterator(dir_ / (out + ".parts")))
        n += f.path().extension() == ".h5" ? 1 : 0;
    return n;
  }
  // Runs `mcref dataset ds.toml -o r.h5` on 2 ranks and kills `rank` (SIGKILL)
  // once r.h5.parts/ holds `parts_done` parts; the job must fail.
  void kill_rank(int rank, int parts_done) {
    const std::string job = "cd '" + dir_.string() + "' && exec " +
                            mcref_ranks_pids(2, "dataset ds.toml -o r.h5 --threads 1 --quiet") + " 2> killed.txt";
    const pid_t launcher = fork();
    ASSERT_GE(launcher, 0);
    if (launcher == 0) {
      execl("/bin/sh", "sh", "-c", job.c_str(), static_cast<char*>(nullptr));
      _exit(127);
    }
    const std::string pid_file = "pid." + std::to_string(rank);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while ((parts("r.h5") < parts_done || !fs::exists(dir_ / pid_file)) && std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    pid_t pid = 0;
    std::ifstream(dir_ / pid_file) >> pid;
    ASSERT_GT(pid, 0);
    ASSERT_EQ(kill(pid, SIGKILL), 0);
    int status = 0;
    ASSERT_EQ(waitpid(launcher, &status, 0), launcher);
    EXPECT_FALSE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "the job should fail when a rank dies";
  }
  // Files in dir_ whose name starts with `prefix`.
  int files(const std::string& prefix) const {
    int n = 0;
    for (const auto& f : fs::directory_iterator(dir_)) n += f.path().filename().string().rfind(prefix, 0) == 0 ? 1 : 0;
    return n;
  }
  fs::path dir_;
};

}  // namespace

TEST_F(DatasetMpi, AnyRankCountGivesTheBytesOfOneProcess) {
  write(300, 5);
  std::string err;
  ASSERT_EQ(shell(dir_, mcref("dataset ds.toml -o one.h5 --threads 1 --quiet"), &err), 0) << err;
  for (int n : {2, 3}) {
    const std::string out = "np" + std::to_string(n) + ".h5";
    ASSERT_EQ(shell(dir_, mcref_ranks(n, "dataset ds.toml -o " + out), &err), 0) << err;
    EXPECT_EQ(rank_codes(dir_, n), std::vector<int>(static_cast<std::size_t>(n), 0));
    // The summary comes from rank 0 alone.
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
    EXPECT_NE(err.find("10 entries (10 simulated, 0 resumed)"), std::string::npos) << err;
    EXPECT_EQ(shell(dir_, "cmp one.h5 " + out, nullptr), 0) << n << " ranks changed the bytes";
    EXPECT_FALSE(fs::exists(dir_ / (out + ".parts")));
  }
  // With a shard split too: the shards merge into the same bytes.
  ASSERT_EQ(shell(dir_, mcref_ranks(2, "dataset ds.toml -o s0.h5 --shard 0/2 --quiet"), &err), 0) << err;
  ASSERT_EQ(shell(dir_, mcref("dataset ds.toml -o s1.h5 --shard 1/2 --quiet"), &err), 0) << err;
  ASSERT_EQ(shell(dir_, mcref("merge s0.h5 s1.h5 -o merged.h5 --quiet"), &err), 0) << err;
  EXPECT_EQ(shell(dir_, "cmp one.h5 merged.h5", nullptr), 0);
}

// The other geometry kinds and slab walks, each a dataset of 4 entries over one
// parameter: 1 process on 1 thread, shards on 2 and 1 threads merged, 2 ranks,
// and a job stopped after one entry then resumed on 2 ranks give the same bytes.
TEST_F(DatasetMpi, EveryGeometryKindGivesTheSameBytesForThreadsShardsRanksAndResume) {
  struct Kind {
    const char* name;
    const char* base;
    const char* key;
    const char* range;
  };
  const char* measure = "[run]\nseed = 1\nbatches = 2\n\n[[measure]]\nquantity = \"brdf\"\ntheta_i_deg = [20, 60]\n"
                        "theta_o_bins = 3\nphi_bins = 2\nsamples = 300\n";
  const std::string micrograin = std::string(R"([geometry]
kind = "micrograin"
tau0 = 0.4
beta = 1.0
tile = 40

[material.grain]
type = "lambertian"
albedo = 0.8

[material.base]
type = "lambertian"
albedo = 0.5

)") + measure;
  const std::string spheres = std::string(R"([geometry]
kind = "spheres"
albedo = 0.8
placement = "rsa"
volume_fraction = 0.1
tile = 20
depth_mfp = 10

)") + measure;
  const std::string vdb_wave = std::string(R"([geometry]
kind = "slab"
backend = "openvdb"
walk = "wave"
tile = 1.0
lateral_voxels = 4
depth_voxels = 16

[[geometry.layer]]
phase = "sggx_surface"
alpha = 0.5
thickness = 1.0
density = 1.0
profile = "linear"
profile_top = 0.5
profile_bottom = 1.5
albedo = 0.9

)") + measure;
  const std::string next_event = with(kBase, "SAMPLES", "300").insert(std::string(kBase).find("\n[["),
                                                                       "\nestimator = \"next_event_mis\"");
  const Kind kinds[] = {
      {"micrograin", micrograin.c_str(), "geometry.tau0", "[0.2, 0.6]"},
      {"spheres", spheres.c_str(), "geometry.albedo", "[0.3, 0.9]"},
      {"openvdb wave", vdb_wave.c_str(), "geometry.layer.0.albedo", "[0.3, 0.9]"},
      {"next-event", next_event.c_str(), "geometry.layer.0.albedo", "[0.3, 0.9]"},
  };
  for (const Kind& k : kinds) {
    SCOPED_TRACE(k.name);
    for (const auto& f : fs::directory_iterator(dir_)) fs::remove_all(f.path());
    std::ofstream(dir_ / "base.toml") << k.base;
    std::ofstream(dir_ / "ds.toml") << "[dataset]\nexperiment = \"base.toml\"\nentries = 4\nseed = 7\n\n[[parameter]]\nkey = \""
                                    << k.key << "\"\nrange = " << k.range << "\n";
    std::string err;
    ASSERT_EQ(shell(dir_, mcref("dataset ds.toml -o one.h5 --threads 1 --quiet"), &err), 0) << err;
    ASSERT_EQ(shell(dir_, mcref("dataset ds.toml -o s0.h5 --shard 0/2 --threads 2 --quiet"), &err), 0) << err;
    ASSERT_EQ(shell(dir_, mcref("dataset ds.toml -o s1.h5 --shard 1/2 --threads 1 --quiet"), &err), 0) << err;
    ASSERT_EQ(shell(dir_, mcref("merge s1.h5 s0.h5 -o merged.h5 --quiet"), &err), 0) << err;
    EXPECT_EQ(shell(dir_, "cmp one.h5 merged.h5", nullptr), 0) << "shards on 2 and 1 threads changed the bytes";
    ASSERT_EQ(shell(dir_, mcref_ranks(2, "dataset ds.toml -o np2.h5 --quiet"), &err), 0) << err;
    EXPECT_EQ(shell(dir_, "cmp one.h5 np2.h5", nullptr), 0) << "2 ranks changed the bytes";
    ASSERT_EQ(shell(dir_, mcref("dataset ds.toml -o r.h5 --stop-after 1 --threads 2 --quiet"), &err), 0) << err;
    EXPECT_EQ(parts("r.h5"), 1);
    ASSERT_EQ(shell(dir_, mcref_ranks(2, "dataset ds.toml -o r.h5 --threads 1"), &err), 0) << err;
    EXPECT_NE(err.find(", 1 resumed)"), std::string::npos) << err;
    EXPECT_EQ(shell(dir_, "cmp one.h5 r.h5", nullptr), 0) << "a resume on 2 ranks changed the bytes";
  }
}

TEST_F(DatasetMpi, StoppedJobAndKilledRankResumeWithAnyRankCount) {
  write(12000, 8);  // 16 entries of about 0.1 s each
  std::string err;
  ASSERT_EQ(shell(dir_, mcref("dataset ds.toml -o ref.h5 --threads 1 --quiet"), &err), 0) << err;
  // A job stopped after 3 entries (over 2 ranks) keeps exactly those.
  ASSERT_EQ(shell(dir_, mcref_ranks(2, "dataset ds.toml -o r.h5 --stop-after 3 --threads 1 --quiet"), &err), 0) << err;
  EXPECT_FALSE(fs::exists(dir_ / "r.h5"));
  EXPECT_EQ(parts("r.h5"), 3);
  // Rank 1 of the next job is killed once 2 more entries are done.
  kill_rank(1, 5);
  EXPECT_FALSE(fs::exists(dir_ / "r.h5"));
  const int kept = parts("r.h5");
  EXPECT_GE(kept, 5);
  EXPECT_LT(kept, 16) << "the kill came too late to test a resume";
  // Resumed on 3 ranks: the finished parts are reused, the bytes are the single-process ones.
  ASSERT_EQ(shell(dir_, mcref_ranks(3, "dataset ds.toml -o r.h5 --threads 1"), &err), 0) << err;
  EXPECT_NE(err.find("resumed)"), std::string::npos) << err;
  EXPECT_NE(err.find(", " + std::to_string(kept) + " resumed)"), std::string::npos) << err;
  EXPECT_EQ(shell(dir_, "cmp ref.h5 r.h5", nullptr), 0) << "resume under MPI changed the bytes";
  EXPECT_FALSE(fs::exists(dir_ / "r.h5.parts"));
}

// Rank 0 assembles r.h5 while the entries are computed: killed midway, it
// leaves the parts and a temporary r.h5.tmp.<pid>; the rerun removes the
// temporary and writes the bytes of one process.
TEST_F(DatasetMpi, KilledRankZeroMidAssemblyResumes) {
  write(12000, 8);  // 16 entries of about 0.1 s each
  std::string err;
  ASSERT_EQ(shell(dir_, mcref("dataset ds.toml -o ref.h5 --threads 1 --quiet"), &err), 0) << err;
  kill_rank(0, 6);
  EXPECT_FALSE(fs::exists(dir_ / "r.h5"));
  EXPECT_EQ(files("r.h5.tmp."), 1) << "rank 0's assembly should have been under way";
  const int kept = parts("r.h5");
  EXPECT_GE(kept, 6);
  EXPECT_LT(kept, 16) << "the kill came too late to test a resume";
  ASSERT_EQ(shell(dir_, mcref_ranks(2, "dataset ds.toml -o r.h5 --threads 1"), &err), 0) << err;
  EXPECT_NE(err.find(", " + std::to_string(kept) + " resumed)"), std::string::npos) << err;
  EXPECT_EQ(shell(dir_, "cmp ref.h5 r.h5", nullptr), 0) << "resume after losing rank 0 changed the bytes";
  EXPECT_EQ(files("r.h5.tmp."), 0) << "the killed assembly's temporary was not removed";
  EXPECT_FALSE(fs::exists(dir_ / "r.h5.parts"));
}

TEST_F(DatasetMpi, BadInputIsOneLineFromRankZeroAndFailsEveryRank) {
  write(300, 2);
  const std::string ds = with(kDataset, "ENTRIES", "2");
  std::ofstream(dir_ / "bad.toml") << with(ds, "range = [0.1, 10.0]", "range = [-2, -1]");
  std::string err;
  shell(dir_, mcref_ranks_failing(2, "dataset bad.toml -o bad.h5"), &err);
  EXPECT_EQ(rank_codes(dir_, 2), (std::vector<int>{2, 2}));
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  EXPECT_EQ(err.rfind("mcref: error: bad.toml: key 'parameter.1.range'", 0), 0u) << err;
  EXPECT_FALSE(fs::exists(dir_ / "bad.h5"));
  EXPECT_FALSE(fs::exists(dir_ / "bad.h5.parts"));
  // Parts of another dataset, found by rank 0 alone: every rank fails alike.
  ASSERT_EQ(shell(dir_, mcref("dataset ds.toml -o x.h5 --stop-after 1 --quiet"), &err), 0) << err;
  std::ofstream(dir_ / "other.toml") << with(ds, "seed = 7", "seed = 8");
  shell(dir_, mcref_ranks_failing(2, "dataset other.toml -o x.h5"), &err);
  EXPECT_EQ(rank_codes(dir_, 2), (std::vector<int>{2, 2}));
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  EXPECT_NE(err.find("x.h5.parts"), std::string::npos) << err;
  EXPECT_NE(err.find("another dataset"), std::string::npos) << err;
}
