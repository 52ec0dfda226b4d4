// Rank 0's assembly beside the computation (sim/dataset/entry_assembler.h):
// whatever order the entries finish in, OUTPUT holds the bytes of a
// single-process run; an assembly stopped before the last entry writes
// nothing and leaves no temporary; a damaged part is an error naming it.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>

#include "sim/dataset/dataset_config.h"
#include "sim/dataset/dataset_file.h"
#include "sim/dataset/dataset_run.h"
#include "sim/dataset/entry_assembler.h"
#include "sim/experiment/config_error.h"

namespace fs = std::filesystem;

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

[run]
seed = 1
batches = 2

[[measure]]
quantity = "brdf"
theta_i_deg = [20, 60]
theta_o_bins = 3
phi_bins = 2
samples = 100
)";

const char* kDataset = R"(
[dataset]
experiment = "base.toml"
entries = 6
seed = 7

[[parameter]]
key = "geometry.layer.0.thickness"
range = [0.1, 10.0]
distribution = "log_uniform"
)";

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

class Assembler : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("mcref_test_entry_assembler_" + std::to_string(getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    std::ofstream(dir_ / "base.toml") << kBase;
    std::ofstream(dir_ / "ds.toml") << kDataset;
    config_ = mcref::load_dataset((dir_ / "ds.toml").string());
    // The reference file of a whole run, and its entries as the parts the ranks write.
    mcref::DatasetRunOptions o;
    o.output = path("ref.h5");
    o.threads = 1;
    o.quiet = true;
    mcref::run_dataset(config_, o);
    fs::create_directories(path("p.h5.parts"));
    mcref::DatasetReader ref(path("ref.h5"));
    for (std::int64_t i = 0; i < 6; ++i) {
      mcref::DatasetWriter w(part(i), mcref::dataset_header(config_, "part"));
      w.add(ref.entry(i));
      w.commit();
    }
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::string part(std::int64_t i) const { return path("p.h5.parts/entry-" + std::to_string(i) + ".h5"); }
  std::unique_ptr<mcref::EntryAssembler> assembler(const std::string& out, const std::vector<bool>& finished) {
    return std::make_unique<mcref::EntryAssembler>(
        path(out), mcref::dataset_header(config_, "all"), std::vector<std::int64_t>{0, 1, 2, 3, 4, 5},
        [this](std::int64_t i) { return part(i); }, finished);
  }
  fs::path dir_;
  mcref::DatasetConfig config_;
};

}  // namespace

TEST_F(Assembler, AnyFinishingOrderGivesTheBytesOfOneProcess) {
  const std::string reference = slurp(path("ref.h5"));
  // In reverse order, with pauses: the thread waits for entry 0, then takes the rest.
  auto reverse = assembler("reverse.h5", std::vector<bool>(6, false));
  for (int k = 5; k >= 0; --k) {
    reverse->finished(static_cast<std::size_t>(k));
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  reverse->commit();
  EXPECT_TRUE(slurp(path("reverse.h5")) == reference) << "the finishing order changed the bytes";
  // Some entries finished before the assembly starts (resumed parts), the rest interleaved.
  auto mixed = assembler("mixed.h5", {false, true, true, false, true, false});
  for (std::size_t k : {3, 0, 5}) mixed->finished(k);
  mixed->commit();
  EXPECT_TRUE(slurp(path("mixed.h5")) == reference);
  // Every entry finished already: the assembly is the whole of it.
  auto all = assembler("all.h5", std::vector<bool>(6, true));
  all->commit();
  EXPECT_TRUE(slurp(path("all.h5")) == reference);
  for (int i = 0; i < 6; ++i) EXPECT_TRUE(fs::exists(part(i))) << "the assembler must leave the parts to its caller";
}

TEST_F(Assembler, StoppedBeforeTheLastEntryWritesNothing) {
  {
    auto a = assembler("stopped.h5", {true, true, true, false, false, false});
    a->finished(3);
    std::this_thread::sleep_for(std::chrono::milliseconds(50));  // entries 0-3 are added meanwhile
  }  // the job failed: destroyed before entries 4 and 5 finished
  for (const auto& f : fs::directory_iterator(dir_))
    EXPECT_EQ(f.path().filename().string().rfind("stopped.h5", 0), std::string::npos) << f.path();
}

TEST_F(Assembler, DamagedPartIsAnErrorNamingIt) {
  std::ofstream(part(2), std::ios::trunc) << "damaged";
  auto a = assembler("bad.h5", std::vector<bool>(6, false));
  a->finished(0);
  a->finished(1);
  a->finished(2);
  try {
    // The error reaches the caller at its next call, or at commit() at the latest.
    for (std::size_t k = 3; k < 6; ++k) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      a->finished(k);
    }
    a->commit();
    FAIL() << "a damaged part was assembled";
  } catch (const mcref::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("entry-2.h5"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(path("bad.h5")));
}
