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

#include "sim/dataset/dataset_file.h"
#include "sim/dataset/entry_assembler.h"
#include "sim/experiment/config_error.h"
#include "sim/tally/table.h"

namespace fs = std::filesystem;

namespace {

// Entry i of a dataset of 6: one small table whose sums depend on i.
mcref::DatasetEntry entry(std::int64_t i) {
  mcref::DatasetEntry e;
  e.index = i;
  e.seed = static_cast<std::uint64_t>(100 + i);
  e.parameters = {0.5 * static_cast<double>(i)};
  e.assignments = "geometry.layer.0.thickness=" + std::to_string(0.5 * static_cast<double>(i));
  e.config = "[run]\nseed = " + std::to_string(100 + i) + "\n";
  mcref::Table t("brdf", "brdf", {mcref::Axis::uniform_bins("theta_o", "rad", 0, 1.5, 3)});
  t.batches = 2;
  t.sum = {1.0 + static_cast<double>(i), 2.0, 3.0};
  t.sum_sq = {2.0 + static_cast<double>(i * i), 2.5, 5.0};
  e.tables.push_back(t);
  return e;
}

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
    fs::create_directories(dir_ / "p.h5.parts");
    header_.mcref_version = "test";
    header_.sim_fingerprint = "test";
    header_.entries = 6;
    header_.columns = {"geometry.layer.0.thickness"};
    // The reference: the 6 entries written in order by one writer, as one process does;
    // and each entry as the part a rank writes.
    mcref::DatasetWriter ref(path("ref.h5"), header_);
    for (std::int64_t i = 0; i < 6; ++i) {
      ref.add(entry(i));
      mcref::DatasetHeader part = header_;
      part.shard = "part";
      mcref::DatasetWriter w(part_path(i), part);
      w.add(entry(i));
      w.commit();
    }
    ref.commit();
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::string part_path(std::int64_t i) const { return path("p.h5.parts/entry-" + std::to_string(i) + ".h5"); }
  std::unique_ptr<mcref::EntryAssembler> assembler(const std::string& out, const std::vector<bool>& finished) {
    return std::make_unique<mcref::EntryAssembler>(
        path(out), header_, std::vector<std::int64_t>{0, 1, 2, 3, 4, 5},
        [this](std::int64_t i) { return part_path(i); }, finished);
  }
  fs::path dir_;
  mcref::DatasetHeader header_;
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
  for (int i = 0; i < 6; ++i) EXPECT_TRUE(fs::exists(part_path(i))) << "the assembler must leave the parts to its caller";
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
  std::ofstream(part_path(2), std::ios::trunc) << "damaged";
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
