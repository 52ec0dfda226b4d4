// mcref dataset / mcref merge: the file of a run is the same byte for byte
// whatever the thread count, after an interruption and resume (from parts
// holding sums, or full parts of earlier builds), and when assembled from
// shards by merge; entries hold what `mcref simulate` with the
// entry's assignments gives; bad shard sets and bad input are one-line errors
// with a non-zero exit and no output file.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "sim/dataset/dataset_config.h"
#include "sim/dataset/dataset_entry.h"
#include "sim/dataset/dataset_file.h"
#include "sim/dataset/dataset_run.h"
#include "sim/experiment/config_error.h"
#include "sim/experiment/simulate.h"
#include "sim/hdf5/h5_util.h"
#include "sim/hdf5/table_file.h"

namespace fs = std::filesystem;
using mcref::ConfigError;

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
samples = 150
)";

const char* kDataset = R"(
[dataset]
experiment = "base.toml"
entries = 3
seed = 7
tables = ["brdf", "brdf_btdf", "brdf_albedo"]

[[parameter]]
key = "geometry.layer.count"
values = [1, 2]

[[parameter]]
key = "geometry.layer.0.alpha"
range = [0.1, 1.0]
distribution = "log_uniform"

[[parameter]]
key = "geometry.layer.0.phase"
choices = ["sggx_surface", "sggx_fiber"]

[[parameter]]
key = "geometry.layer.1.albedo"
range = [0.0, 1.0]
size = 3
)";

// Rewrites a dataset file with its header changed (as another build would have written it).
void rewrite(const std::string& file, const std::function<void(mcref::DatasetHeader&)>& change) {
  mcref::DatasetHeader h;
  std::vector<mcref::DatasetEntry> entries;
  {
    mcref::DatasetReader r(file);
    h = r.header();
    for (std::int64_t i : r.indices()) entries.push_back(r.entry(i));
  }
  change(h);
  mcref::DatasetWriter w(file, h);
  for (const mcref::DatasetEntry& e : entries) w.add(e);
  w.commit();
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

class DatasetRun : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("mcref_test_dataset_files_" + std::to_string(getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    std::ofstream(dir_ / "base.toml") << kBase;
    std::ofstream(dir_ / "ds.toml") << kDataset;
    config_ = mcref::load_dataset((dir_ / "ds.toml").string());
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  mcref::DatasetRunSummary run(const std::string& out, int shard = 0, int shards = 1, int threads = 1,
                               std::int64_t stop_after = -1) {
    mcref::DatasetRunOptions o;
    o.output = path(out);
    o.shard = shard;
    o.shards = shards;
    o.threads = threads;
    o.quiet = true;
    o.stop_after = stop_after;
    return mcref::run_dataset(config_, o);
  }
  // Runs the mcref binary; returns the exit code, stderr in *err.
  int cli(const std::string& args, std::string* err) {
    const std::string cmd = std::string("cd '") + dir_.string() + "' && '" + MCREF_BINARY + "' " + args + " 2> err.txt";
    const int status = std::system(cmd.c_str());
    *err = slurp(dir_ / "err.txt");
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  fs::path dir_;
  mcref::DatasetConfig config_;
};

}  // namespace

TEST_F(DatasetRun, FileHoldsParametersAndTheEntriesTables) {
  const mcref::DatasetRunSummary s = run("full.h5");
  EXPECT_TRUE(s.complete);
  EXPECT_EQ(s.computed, 6);
  EXPECT_FALSE(fs::exists(path("full.h5.parts")));
  mcref::DatasetReader r(path("full.h5"));
  EXPECT_EQ(r.header().shard, "all");
  EXPECT_EQ(r.header().entries, 6);
  EXPECT_EQ(r.indices(), (std::vector<std::int64_t>{0, 1, 2, 3, 4, 5}));
  EXPECT_EQ(r.header().columns.size(), 6u);
  EXPECT_EQ(r.header().labels.at("geometry.layer.0.phase"), (std::vector<std::string>{"sggx_surface", "sggx_fiber"}));
  // Entry 4 (two layers) is what simulate gives for its assignments.
  const mcref::DatasetEntry e = r.entry(4);
  const mcref::EntryPlan plan = mcref::plan_entry(config_, 4);
  EXPECT_EQ(e.parameters.size(), plan.columns.size());
  for (std::size_t k = 0; k < e.parameters.size(); ++k) EXPECT_EQ(e.parameters[k], plan.columns[k]);
  mcref::SimulateOptions so;
  so.quiet = true;
  std::vector<std::string> sets;
  for (std::size_t a = 0, b; a < e.assignments.size(); a = b + 1) {
    b = e.assignments.find('\n', a);
    if (b == std::string::npos) b = e.assignments.size();
    const std::string line = e.assignments.substr(a, b - a);
    if (line.rfind("geometry.layer.count", 0) != 0) sets.push_back(line);
  }
  const std::vector<mcref::Table> direct = mcref::simulate(mcref::load_experiment(path("base.toml"), sets), so);
  ASSERT_EQ(e.tables.size(), 3u);  // the tables asked for, in name order
  EXPECT_EQ(e.tables[0].name, "brdf");
  for (const mcref::Table& t : e.tables)
    for (const mcref::Table& d : direct)
      if (d.name == t.name) {
        EXPECT_EQ(t.sum, d.sum) << t.name;
        EXPECT_EQ(t.sum_sq, d.sum_sq) << t.name;
        EXPECT_EQ(t.batches, 2);
      }
  // One-layer entries: layer 1's albedo does not apply.
  EXPECT_TRUE(std::isnan(r.entry(0).parameters[3]));
  // A second run finds the file up to date.
  EXPECT_TRUE(run("full.h5").up_to_date);
}

TEST_F(DatasetRun, ThreadCountResumeShardsAndMergeGiveTheSameBytes) {
  run("full.h5", 0, 1, 1);
  const std::string reference = slurp(path("full.h5"));
  run("threads.h5", 0, 1, 2);
  EXPECT_TRUE(slurp(path("threads.h5")) == reference) << "thread count changed the bytes";
  // Interrupted after 3 entries: no output, finished parts kept.
  const mcref::DatasetRunSummary first = run("resumed.h5", 0, 1, 2, 3);
  EXPECT_FALSE(first.complete);
  EXPECT_FALSE(fs::exists(path("resumed.h5")));
  EXPECT_TRUE(fs::exists(path("resumed.h5.parts/entry-2.h5")));
  // Lose a part, leave a half-written temporary and a damaged part behind.
  fs::remove(path("resumed.h5.parts/entry-1.h5"));
  std::ofstream(path("resumed.h5.parts/entry-3.h5.tmp.999999")) << "half written";
  std::ofstream(path("resumed.h5.parts/entry-4.h5")) << "damaged";
  const mcref::DatasetRunSummary second = run("resumed.h5", 0, 1, 1);
  EXPECT_TRUE(second.complete);
  EXPECT_EQ(second.reused, 2);
  EXPECT_EQ(second.computed, 4);
  EXPECT_TRUE(slurp(path("resumed.h5")) == reference) << "resume changed the bytes";
  EXPECT_FALSE(fs::exists(path("resumed.h5.parts")));
  // Three shards with different thread counts, merged in any order.
  run("s0.h5", 0, 3, 1);
  run("s1.h5", 1, 3, 2);
  run("s2.h5", 2, 3, 1);
  EXPECT_EQ(mcref::DatasetReader(path("s1.h5")).indices(), (std::vector<std::int64_t>{1, 4}));
  EXPECT_EQ(mcref::merge_datasets({path("s2.h5"), path("s0.h5"), path("s1.h5")}, path("merged.h5"), true), 6);
  EXPECT_TRUE(slurp(path("merged.h5")) == reference) << "merge is not bit-identical to the single run";
  // The same through the command line, compared with cmp.
  std::string err;
  ASSERT_EQ(cli("dataset ds.toml -o c0.h5 --shard 0/2 --quiet", &err), 0) << err;
  ASSERT_EQ(cli("dataset ds.toml -o c1.h5 --shard 1/2 --threads 2 --quiet", &err), 0) << err;
  ASSERT_EQ(cli("merge c1.h5 c0.h5 -o cli.h5 --quiet", &err), 0) << err;
  EXPECT_EQ(std::system(("cmp -s '" + path("cli.h5") + "' '" + path("full.h5") + "'").c_str()), 0);
}

// A run stopped after OUTPUT was committed, while it removed the parts, left
// them there for good: a run that finds OUTPUT up to date now removes this
// dataset's parts and temporaries (and the directory, once empty).
TEST_F(DatasetRun, PartsLeftBesideACommittedOutputAreRemoved) {
  run("out.h5", 0, 1, 1, 2);  // two parts
  run("whole.h5");
  fs::copy_file(path("whole.h5"), path("out.h5"));
  std::ofstream(path("out.h5.parts/entry-3.h5.tmp.999999")) << "half written";
  const mcref::DatasetRunSummary again = run("out.h5");
  EXPECT_TRUE(again.up_to_date);
  EXPECT_FALSE(fs::exists(path("out.h5.parts"))) << "parts left beside the committed output";
  EXPECT_TRUE(slurp(path("out.h5")) == slurp(path("whole.h5")));
}

// A part holds its tables' sums only (storage "sums" on the root and on each
// table, no value nor stderr dataset) and reads back as the entry the
// assembled file holds (the same sums and batches). A part in full storage
// (as builds before this one wrote them) still resumes into the same bytes,
// and parts merged by hand make a full file, the same bytes again.
TEST_F(DatasetRun, PartsHoldTheSumsAndFullPartsStillResume) {
  run("full.h5", 0, 1, 1);
  const std::string reference = slurp(path("full.h5"));
  run("p.h5", 0, 1, 1, 2);
  const std::string part0 = path("p.h5.parts/entry-0.h5"), part1 = path("p.h5.parts/entry-1.h5");
  {
    const mcref::DatasetReader r(part0);
    EXPECT_TRUE(r.header().sums);
    const mcref::DatasetEntry e = r.entry(0), f = mcref::DatasetReader(path("full.h5")).entry(0);
    ASSERT_EQ(e.tables.size(), 3u);
    ASSERT_EQ(e.tables.size(), f.tables.size());
    for (std::size_t i = 0; i < e.tables.size(); ++i) {
      EXPECT_EQ(e.tables[i].name, f.tables[i].name);
      EXPECT_EQ(e.tables[i].batches, f.tables[i].batches);
      EXPECT_EQ(e.tables[i].sum, f.tables[i].sum) << e.tables[i].name;
      EXPECT_EQ(e.tables[i].sum_sq, f.tables[i].sum_sq) << e.tables[i].name;
    }
    hid_t file = H5Fopen(part0.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    ASSERT_GE(file, 0);
    {
      mcref::h5::Handle root = mcref::h5::open_group(file, "/");
      EXPECT_EQ(mcref::h5::read_string_attr(root, "storage"), "sums");
      for (const char* table : {"brdf", "brdf_btdf", "brdf_albedo"}) {
        mcref::h5::Handle g = mcref::h5::open_group(file, std::string("entries/0/") + table);
        EXPECT_EQ(mcref::h5::read_string_attr(g, "storage"), "sums") << table;
        EXPECT_TRUE(mcref::h5::exists(g, "sum") && mcref::h5::exists(g, "sum_sq")) << table;
        EXPECT_FALSE(mcref::h5::exists(g, "value") || mcref::h5::exists(g, "stderr")) << table;
      }
    }
    H5Fclose(file);
  }
  // Part 1 rewritten in full storage, as earlier builds wrote parts.
  rewrite(part1, [](mcref::DatasetHeader& h) { h.sums = false; });
  EXPECT_FALSE(mcref::DatasetReader(part1).header().sums);
  const mcref::DatasetRunSummary resumed = run("p.h5");
  EXPECT_TRUE(resumed.complete);
  EXPECT_EQ(resumed.reused, 2);
  EXPECT_TRUE(slurp(path("p.h5")) == reference) << "resume from sums and full parts changed the bytes";
  // Parts given to merge as shards (with the last entry's shard file) give a full file: the reference.
  run("q.h5", 0, 1, 1, 5);
  run("q5.h5", 5, 6, 1);
  std::vector<std::string> shards;  // a part first: the result takes the first file's header
  for (int i = 0; i < 5; ++i) shards.push_back(path("q.h5.parts/entry-" + std::to_string(i) + ".h5"));
  shards.push_back(path("q5.h5"));
  EXPECT_EQ(mcref::merge_datasets(shards, path("merged.h5"), true), 6);
  EXPECT_FALSE(mcref::DatasetReader(path("merged.h5")).header().sums);
  EXPECT_TRUE(slurp(path("merged.h5")) == reference) << "parts merged by hand differ from the run";
}

// Parts and shards combine when the build that simulated them had this
// build's simulation fingerprint, whatever its git commit (a change to
// validate/ or the README keeps a half-done dataset); another fingerprint, or
// none (files from before it), is an error naming both builds.
TEST_F(DatasetRun, PartsAndShardsCombineByTheSimulationFingerprintNotTheCommit) {
  run("full.h5");
  const std::string reference = slurp(path("full.h5"));
  EXPECT_EQ(mcref::DatasetReader(path("full.h5")).header().sim_fingerprint, mcref::mcref_sim_fingerprint());
  auto other_commit = [](mcref::DatasetHeader& h) { h.git_commit = "0123456789ab-dirty"; };
  auto other_fingerprint = [](mcref::DatasetHeader& h) { h.sim_fingerprint = "00112233aabbccdd"; };
  auto no_fingerprint = [](mcref::DatasetHeader& h) { h.sim_fingerprint.clear(); };
  // Resume: a part of another commit is kept; the file is the reference.
  run("r.h5", 0, 1, 1, 3);
  rewrite(path("r.h5.parts/entry-1.h5"), other_commit);
  const mcref::DatasetRunSummary resumed = run("r.h5");
  EXPECT_EQ(resumed.reused, 3);
  EXPECT_TRUE(slurp(path("r.h5")) == reference) << "resume across commits changed the bytes";
  // A part simulated by another simulation (or by an mcref from before fingerprints).
  const std::vector<std::pair<std::function<void(mcref::DatasetHeader&)>, std::string>> others{
      {other_fingerprint, "simulation fingerprint 00112233aabbccdd"}, {no_fingerprint, "simulation fingerprint none"}};
  for (const auto& [change, named] : others) {
    fs::remove_all(path("f.h5.parts"));
    run("f.h5", 0, 1, 1, 2);
    rewrite(path("f.h5.parts/entry-0.h5"), change);
    try {
      run("f.h5");
      ADD_FAILURE() << "a part of another simulation was mixed in";
    } catch (const ConfigError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("f.h5.parts"), std::string::npos) << what;
      EXPECT_NE(what.find("simulation fingerprint " + mcref::mcref_sim_fingerprint()), std::string::npos) << what;
      EXPECT_NE(what.find(named), std::string::npos) << what;
    }
    EXPECT_FALSE(fs::exists(path("f.h5")));
  }
  // Merge: a shard of another commit merges into the reference bytes; one of
  // another simulation is refused, naming it.
  run("s0.h5", 0, 2);
  run("s1.h5", 1, 2);
  rewrite(path("s1.h5"), other_commit);
  EXPECT_EQ(mcref::merge_datasets({path("s1.h5"), path("s0.h5")}, path("merged.h5"), true), 6);
  EXPECT_TRUE(slurp(path("merged.h5")) == reference) << "merge across commits changed the bytes";
  rewrite(path("s1.h5"), other_fingerprint);
  try {
    mcref::merge_datasets({path("s0.h5"), path("s1.h5")}, path("m2.h5"), true);
    ADD_FAILURE() << "shards of another simulation were merged";
  } catch (const ConfigError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("s1.h5"), std::string::npos) << what;
    EXPECT_NE(what.find("simulation fingerprint 00112233aabbccdd"), std::string::npos) << what;
  }
  EXPECT_FALSE(fs::exists(path("m2.h5")));
}

TEST_F(DatasetRun, BadShardSetsAreErrors) {
  run("s0.h5", 0, 2);
  run("s1.h5", 1, 2);
  auto merge_error = [&](std::vector<std::string> in) {
    try {
      mcref::merge_datasets(in, path("out.h5"), true);
    } catch (const ConfigError& e) {
      EXPECT_FALSE(fs::exists(path("out.h5")));
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(merge_error({path("s0.h5"), path("s0.h5")}).find("overlaps"), std::string::npos);
  EXPECT_NE(merge_error({path("s0.h5")}).find("3 of 6 entries are missing from the shards given (entries 1, 3, 5)"),
            std::string::npos);
  // A part of a 2^40-entry dataset (2 grid points x 2^39 entries), merged
  // alone: its missing entries are counted without a table of the declared
  // size (it was std::bad_alloc, 4 TB of owners).
  {
    std::string big = kDataset;
    big.replace(big.find("entries = 3"), 11, "entries = 549755813888");
    std::ofstream(dir_ / "big.toml") << big;
    const mcref::DatasetConfig keep = config_;
    config_ = mcref::load_dataset(path("big.toml"));
    run("big.h5", 0, 1, 1, 1);
    config_ = keep;
    const std::string e = merge_error({path("big.h5.parts/entry-0.h5")});
    EXPECT_NE(e.find("1099511627775 of 1099511627776 entries are missing from the shards given (entries 1, 2, 3, 4, 5, "
                     "6, 7, 8, ...)"),
              std::string::npos)
        << e;
  }
  // A shard of another seed.
  std::string text = kDataset;
  text.replace(text.find("seed = 7"), 8, "seed = 8");
  std::ofstream(dir_ / "other.toml") << text;
  config_ = mcref::load_dataset(path("other.toml"));
  run("other1.h5", 1, 2);
  const std::string e = merge_error({path("s0.h5"), path("other1.h5")});
  EXPECT_NE(e.find("other1.h5"), std::string::npos) << e;
  EXPECT_NE(e.find("seed"), std::string::npos) << e;
  // Not a dataset file.
  EXPECT_NE(merge_error({path("s0.h5"), path("base.toml")}).find("not an HDF5 file"), std::string::npos);
  // Parts or an output of another dataset are not silently mixed in.
  EXPECT_THROW(run("s0.h5", 0, 2), ConfigError);
}

TEST_F(DatasetRun, CommandLineErrorsAreOneLineAndWriteNothing) {
  std::ofstream(dir_ / "bad.toml") << "[dataset]\nexperiment = \"base.toml\"\nentries = 4\n"
                                      "[[parameter]]\nkey = \"geometry.layer.0.alpha\"\nrange = [-2, -1]\n";
  std::string err;
  EXPECT_EQ(cli("dataset bad.toml -o bad.h5", &err), 2);
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  EXPECT_NE(err.find("bad.toml: key 'geometry.layer.0.alpha': -2 (the lower end of range)"), std::string::npos) << err;
  EXPECT_NE(err.find("geometry.layer.0.alpha"), std::string::npos) << err;
  EXPECT_NE(err.find("[0.0001, 1000]"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(path("bad.h5")));
  EXPECT_FALSE(fs::exists(path("bad.h5.parts")));
  for (const char* shard : {"3/3", "1/2/3", "0/0", "x/2"}) {  // the value as given (it said "= 2/3" for 1/2/3)
    EXPECT_EQ(cli(std::string("dataset ds.toml -o x.h5 --shard ") + shard, &err), 2);
    EXPECT_NE(err.find(std::string("key '--shard': = ") + shard + " must be K/N"), std::string::npos) << err;
  }
  EXPECT_EQ(cli("dataset ds.toml", &err), 2);
  EXPECT_EQ(cli("merge -o x.h5", &err), 2);
  EXPECT_FALSE(fs::exists(path("x.h5")));
  EXPECT_EQ(cli("dataset --help", &err), 0);
  EXPECT_EQ(cli("merge --help", &err), 0);
}
