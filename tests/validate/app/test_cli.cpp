// The mcref command line (MCREF_BINARY): bad input gives a non-zero exit, one
// line on stderr naming the file, the key and the allowed range, and writes
// nothing; --help works for every verb; a failed run never replaces a good
// table file.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

struct Result {
  int exit_code = -1;
  std::string out, err;
};

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

std::string quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// Lines of a text, without the trailing newline.
std::vector<std::string> lines(const std::string& s) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : s) {
    if (c == '\n') {
      out.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  if (!cur.empty()) out.push_back(cur);
  return out;
}

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("mcref_test_cli_" + std::to_string(getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  // Runs mcref with the given (already quoted) arguments, capturing stdout
  // and stderr in files of the scratch directory.
  Result mcref(const std::string& args) const {
    const std::string out = path("stdout.txt"), err = path("stderr.txt");
    const std::string cmd = quote(MCREF_BINARY) + " " + args + " > " + quote(out) + " 2> " + quote(err);
    const int status = std::system(cmd.c_str());
    Result r;
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = slurp(out);
    r.err = slurp(err);
    fs::remove(out);
    fs::remove(err);
    return r;
  }

  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(path(name), std::ios::binary) << text;
    return path(name);
  }

  // Entries of the scratch directory other than the given ones.
  std::vector<std::string> stray(const std::vector<std::string>& expected) const {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(dir_)) {
      const std::string n = e.path().filename().string();
      bool known = false;
      for (const std::string& x : expected) known = known || x == n;
      if (!known) out.push_back(n);
    }
    return out;
  }

  // A bad `mcref simulate` run: non-zero exit, one stderr line holding every
  // `expected` piece, no output file and no temporary left.
  void expect_rejected(const std::string& toml, const std::vector<std::string>& expected,
                       const std::string& extra_args = "") {
    const std::string exp = write("bad.toml", toml);
    const std::string out = path("out.h5");
    const Result r = mcref("simulate " + quote(exp) + " -o " + quote(out) + " --quiet " + extra_args);
    expect_one_line_error(r, expected);
    EXPECT_FALSE(fs::exists(out)) << "an output file was written";
    for (const std::string& s : stray({"bad.toml"})) ADD_FAILURE() << "left behind: " << s;
  }

  static void expect_one_line_error(const Result& r, const std::vector<std::string>& expected) {
    EXPECT_NE(r.exit_code, 0) << "stderr: " << r.err;
    const std::vector<std::string> ls = lines(r.err);
    ASSERT_EQ(ls.size(), 1u) << "stderr is not one line:\n" << r.err;
    for (const std::string& piece : expected)
      EXPECT_NE(ls[0].find(piece), std::string::npos) << "'" << piece << "' missing from: " << ls[0];
  }

  fs::path dir_;
};

// A small valid experiment; `geometry`, `run` and `measure` replace the sections.
std::string experiment(const std::string& geometry = "tau0 = 0.5\nbeta = 0.8\n", const std::string& run = "",
                       const std::string& measure = "quantity = \"tau_plus\"\ntheta_i_deg = [30]\nsamples = 2000\n") {
  return "[geometry]\nkind = \"micrograin\"\ntile = 20\n" + geometry + "\n[run]\nseed = 3\nbatches = 2\n" + run +
         "\n[[measure]]\n" + measure;
}

}  // namespace

TEST_F(Cli, GoodRunWritesATableFileThatInfoReads) {
  const std::string exp = write("good.toml", experiment());
  const std::string out = path("good.h5");
  const Result r = mcref("simulate " + quote(exp) + " -o " + quote(out) + " --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  ASSERT_TRUE(fs::exists(out));
  EXPECT_TRUE(stray({"good.toml", "good.h5"}).empty());
  const Result info = mcref("info " + quote(out));
  EXPECT_EQ(info.exit_code, 0) << info.err;
  EXPECT_NE(info.out.find("tau_plus"), std::string::npos) << info.out;
}

TEST_F(Cli, Tau0OutOfRangeIsRejected) {
  expect_rejected(experiment("tau0 = 0\nbeta = 0.8\n"), {"bad.toml", "geometry.tau0", "(0, 1)"});
  expect_rejected(experiment("tau0 = 1.5\nbeta = 0.8\n"), {"bad.toml", "geometry.tau0", "(0, 1)"});
}

TEST_F(Cli, BetaOutOfRangeIsRejected) {
  expect_rejected(experiment("tau0 = 0.5\nbeta = 0\n"), {"bad.toml", "geometry.beta", "(0, 100]"});
  expect_rejected(experiment("tau0 = 0.5\nbeta = -1\n"), {"bad.toml", "geometry.beta", "(0, 100]"});
  expect_rejected(experiment("tau0 = 0.5\nbeta_x = 0.5\nbeta_y = -2\n"), {"bad.toml", "geometry.beta_y", "(0, 100]"});
}

TEST_F(Cli, BatchesOutOfRangeIsRejected) {
  // [run] in experiment() sets batches = 2 already; replace the whole section.
  const std::string toml = "[geometry]\nkind = \"micrograin\"\ntile = 20\ntau0 = 0.5\nbeta = 0.8\n"
                           "[run]\nbatches = 0\n[[measure]]\nquantity = \"tau_plus\"\ntheta_i_deg = [30]\nsamples = 100\n";
  expect_rejected(toml, {"bad.toml", "run.batches", "[2, 1000000]"});
}

TEST_F(Cli, SamplesOutOfRangeIsRejected) {
  for (const char* v : {"0", "-5"})
    expect_rejected(experiment("tau0 = 0.5\nbeta = 0.8\n", "",
                               std::string("quantity = \"tau_plus\"\ntheta_i_deg = [30]\nsamples = ") + v + "\n"),
                    {"bad.toml", "measure.0.samples", "[1, "});
}

TEST_F(Cli, UnknownQuantityIsRejected) {
  expect_rejected(experiment("tau0 = 0.5\nbeta = 0.8\n", "", "quantity = \"albedo_of_unicorns\"\nsamples = 100\n"),
                  {"bad.toml", "measure.0.quantity", "albedo_of_unicorns", "\"tau_plus\""});
}

TEST_F(Cli, UnknownKeysAreRejected) {
  expect_rejected(experiment("tau0 = 0.5\nbeta = 0.8\ncolour = \"red\"\n"), {"bad.toml", "geometry.colour"});
  expect_rejected(experiment("tau0 = 0.5\nbeta = 0.8\n", "thredas = 2\n"), {"bad.toml", "run.thredas"});
  expect_rejected(experiment("tau0 = 0.5\nbeta = 0.8\n", "",
                             "quantity = \"tau_plus\"\ntheta_i_deg = [30]\nsamples = 100\nsampels = 5\n"),
                  {"bad.toml", "measure.0.sampels"});
  expect_rejected(experiment() + "\n[tpyo]\nx = 1\n", {"bad.toml", "tpyo"});
}

TEST_F(Cli, TomlSyntaxErrorIsRejected) {
  expect_rejected("[geometry]\nkind = \"micrograin\"\ntau0 = = 0.5\n", {"bad.toml", "line 3"});
  expect_rejected("[geometry\nkind = \"micrograin\"\n", {"bad.toml", "line 1"});
}

TEST_F(Cli, MissingExperimentFileIsRejected) {
  const std::string missing = path("no_such_experiment.toml");
  const Result r = mcref("simulate " + quote(missing) + " -o " + quote(path("out.h5")) + " --quiet");
  expect_one_line_error(r, {"no_such_experiment.toml"});
  EXPECT_FALSE(fs::exists(path("out.h5")));
  EXPECT_TRUE(stray({}).empty());
}

TEST_F(Cli, InfoRejectsFilesThatAreNotMcrefTables) {
  const std::string text = write("notes.txt", "just some text\n");
  expect_one_line_error(mcref("info " + quote(text)), {"notes.txt"});
  // An HDF5 file that mcref did not write (no mcref_format attribute).
  const std::string foreign = path("foreign.h5");
  {
    const hid_t f = H5Fcreate(foreign.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    ASSERT_GE(f, 0);
    H5Gclose(H5Gcreate2(f, "p1", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
    H5Fclose(f);
  }
  expect_one_line_error(mcref("info " + quote(foreign)), {"foreign.h5", "mcref_format"});
  // A damaged mcref file: the first third of a good one.
  const std::string exp = write("good.toml", experiment());
  const std::string good = path("good.h5");
  ASSERT_EQ(mcref("simulate " + quote(exp) + " -o " + quote(good) + " --quiet").exit_code, 0);
  const std::string bytes = slurp(good);
  write("truncated.h5", bytes.substr(0, bytes.size() / 3));
  expect_one_line_error(mcref("info " + quote(path("truncated.h5"))), {"truncated.h5"});
  expect_one_line_error(mcref("info " + quote(path("missing.h5"))), {"missing.h5"});
  expect_one_line_error(mcref("info " + quote(dir_.string())), {dir_.string()});
}

TEST_F(Cli, UnknownVerbAndUnknownOptionAreRejected) {
  expect_one_line_error(mcref("frobnicate"), {"frobnicate", "simulate"});
  const std::string exp = write("good.toml", experiment());
  const std::string out = path("out.h5");
  expect_one_line_error(mcref("simulate " + quote(exp) + " -o " + quote(out) + " --frobnicate"), {"--frobnicate"});
  expect_one_line_error(mcref("info --frobnicate x.h5"), {"--frobnicate"});
  expect_one_line_error(mcref("simulate " + quote(exp) + " -o " + quote(out) + " --threads 0"), {"--threads", "[1, 1024]"});
  expect_one_line_error(mcref("simulate " + quote(exp) + " -o " + quote(out) + " --seed -3"), {"--seed"});
  expect_one_line_error(mcref("simulate " + quote(exp) + " --quiet"), {"-o"});
  expect_one_line_error(mcref("simulate " + quote(exp) + " -o"), {"-o"});
  EXPECT_FALSE(fs::exists(out));
  EXPECT_TRUE(stray({"good.toml"}).empty());
}

TEST_F(Cli, SetWithBadKeyPathIsRejected) {
  const std::string exp = write("good.toml", experiment());
  const std::string out = path("out.h5");
  auto run = [&](const std::string& set) {
    return mcref("simulate " + quote(exp) + " -o " + quote(out) + " --quiet --set " + quote(set));
  };
  expect_one_line_error(run("geometry.colour=red"), {"good.toml", "geometry.colour"});
  expect_one_line_error(run("geometry.tau0.x=1"), {"good.toml", "geometry.tau0.x"});
  expect_one_line_error(run("measure.7.samples=10"), {"good.toml", "measure.7.samples", "[0, 1)"});
  expect_one_line_error(run("=5"), {"good.toml", "key=value"});
  expect_one_line_error(run("geometry.tau0=2"), {"good.toml", "geometry.tau0", "(0, 1)"});
  EXPECT_FALSE(fs::exists(out));
  EXPECT_TRUE(stray({"good.toml"}).empty());
  // A good --set works.
  EXPECT_EQ(run("geometry.tau0=0.3").exit_code, 0);
  EXPECT_TRUE(fs::exists(out));
}

TEST_F(Cli, HelpWorksForEveryVerb) {
  for (const char* args : {"--help", "-h", "help", "simulate --help", "validate --help", "info --help"}) {
    const Result r = mcref(args);
    EXPECT_EQ(r.exit_code, 0) << args << ": " << r.err;
    EXPECT_NE(r.out.find("usage"), std::string::npos) << args << " printed:\n" << r.out;
  }
  // No arguments: usage on stderr, non-zero.
  const Result none = mcref("");
  EXPECT_NE(none.exit_code, 0);
  EXPECT_NE(none.err.find("usage"), std::string::npos);
}

// A good run, then a bad run (bad --set, and a run that fails only after the
// simulation: output into a directory) to the same -o path: the good file is
// byte-identical afterwards.
TEST_F(Cli, FailedRunLeavesAnExistingGoodFileUnchanged) {
  const std::string exp = write("good.toml", experiment());
  const std::string out = path("tables.h5");
  ASSERT_EQ(mcref("simulate " + quote(exp) + " -o " + quote(out) + " --quiet").exit_code, 0);
  const std::string before = slurp(out);
  ASSERT_FALSE(before.empty());
  const Result bad_set = mcref("simulate " + quote(exp) + " -o " + quote(out) + " --quiet --set geometry.tau0=7");
  EXPECT_NE(bad_set.exit_code, 0);
  const std::string bad = write("bad.toml", experiment("tau0 = 0.5\nbeta = 0\n"));
  EXPECT_NE(mcref("simulate " + quote(bad) + " -o " + quote(out) + " --quiet").exit_code, 0);
  EXPECT_EQ(slurp(out), before) << "a failed run changed the good file";
  for (const std::string& s : stray({"good.toml", "bad.toml", "tables.h5"})) ADD_FAILURE() << "left behind: " << s;
  // Output into a missing directory fails at write time and names the path.
  const std::string nowhere = path("no/such/dir/tables.h5");
  expect_one_line_error(mcref("simulate " + quote(exp) + " -o " + quote(nowhere) + " --quiet"), {nowhere});
  EXPECT_FALSE(fs::exists(path("no")));
}
