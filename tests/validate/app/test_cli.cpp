// The mcref command line (MCREF_BINARY): bad input gives a non-zero exit, one
// line on stderr naming the file, the key and the allowed range, and writes
// nothing; --help works for every verb; a failed run never replaces a good
// table file.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <cstring>
#include <filesystem>
#include <string>

#include "sim/hdf5/table_file.h"
#include "tests/validate/app/cli_fixture.h"

namespace fs = std::filesystem;
using namespace mcref_test;

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

// --batch-values: the file holds each batch's estimates (info says so), and
// its sums are those of a run without them.
TEST_F(Cli, BatchValuesAreWrittenOnRequest) {
  const std::string exp = write("good.toml", experiment());
  const std::string plain = path("plain.h5"), kept = path("kept.h5");
  ASSERT_EQ(mcref("simulate " + quote(exp) + " -o " + quote(plain) + " --quiet").exit_code, 0);
  const Result r = mcref("simulate " + quote(exp) + " -o " + quote(kept) + " --batch-values --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const mcref::TableFile a = mcref::read_table_file(plain), b = mcref::read_table_file(kept);
  ASSERT_EQ(a.tables.size(), b.tables.size());
  for (std::size_t k = 0; k < a.tables.size(); ++k) {
    EXPECT_FALSE(a.tables[k].has_batch_values());
    EXPECT_TRUE(b.tables[k].has_batch_values());
    EXPECT_EQ(a.tables[k].sum, b.tables[k].sum);
  }
  EXPECT_EQ(mcref("info " + quote(plain)).out.find("values kept"), std::string::npos);
  EXPECT_NE(mcref("info " + quote(kept)).out.find("(values kept)"), std::string::npos);
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
  // A dataset file: said to be one.
  write("ds.toml", "[dataset]\nexperiment = \"good.toml\"\n[[parameter]]\nkey = \"geometry.tau0\"\nvalues = [0.5]\n");
  ASSERT_EQ(mcref("dataset " + quote(path("ds.toml")) + " -o " + quote(path("ds.h5")) + " --quiet").exit_code, 0);
  expect_one_line_error(mcref("info " + quote(path("ds.h5"))), {"ds.h5", "is an mcref dataset file, not a table file"});
}

TEST_F(Cli, UnknownVerbAndUnknownOptionAreRejected) {
  expect_one_line_error(mcref("frobnicate"), {"frobnicate", "simulate"});
  const std::string exp = write("good.toml", experiment());
  const std::string out = path("out.h5");
  expect_one_line_error(mcref("simulate " + quote(exp) + " -o " + quote(out) + " --frobnicate"), {"--frobnicate"});
  expect_one_line_error(mcref("info --frobnicate x.h5"), {"--frobnicate"});
  // --threads where nothing runs in parallel is refused, not ignored.
  expect_one_line_error(mcref("export-vdb " + quote(exp) + " -o " + quote(path("g.vdb")) + " --threads 2"),
                        {"--threads", "unknown option for 'mcref export-vdb'"});
  expect_one_line_error(mcref("info " + quote(exp) + " --threads 2"), {"--threads", "unknown option for 'mcref info'"});
  // A missing value is named, not taken from the next option.
  expect_one_line_error(mcref("export-brdf x.h5 --table --format merl -o " + quote(path("m.binary"))),
                        {"--table", "needs a value, and --format is an option"});
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

// --version names the same version and commit as the provenance of the
// files this binary writes.
TEST_F(Cli, VersionMatchesTheProvenanceOfWrittenFiles) {
  const Result v = mcref("--version");
  ASSERT_EQ(v.exit_code, 0) << v.err;
  ASSERT_EQ(lines(v.out).size(), 1u) << v.out;
  const std::string exp = write("x.toml", experiment());
  ASSERT_EQ(mcref("simulate " + quote(exp) + " -o " + quote(path("t.h5")) + " --quiet").exit_code, 0);
  const Result info = mcref("info " + quote(path("t.h5")));
  ASSERT_EQ(info.exit_code, 0) << info.err;
  EXPECT_NE(info.out.find("  " + lines(v.out)[0] + ", created"), std::string::npos)
      << "--version: " << v.out << "info: " << info.out;
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
  // Output into a missing directory fails before any work and names the path.
  const std::string nowhere = path("no/such/dir/tables.h5");
  expect_one_line_error(mcref("simulate " + quote(exp) + " -o " + quote(nowhere) + " --quiet"), {nowhere});
  EXPECT_FALSE(fs::exists(path("no")));
}

// validate --case runs only the matching cases (shell wildcards, repeatable);
// a pattern that matches nothing is refused before any work, listing the cases.
TEST_F(Cli, ValidateCaseFilterRunsOnlyMatchingCases) {
  write("x.toml", experiment());
  write("suite.toml",
        "[suite]\nname = \"s\"\n"
        "[[case]]\nname = \"tau_a\"\nexperiment = \"x.toml\"\n"
        "[[case]]\nname = \"tau_b\"\nexperiment = \"x.toml\"\n"
        "[[case]]\nname = \"other\"\nexperiment = \"x.toml\"\n");
  fs::create_directories(path("out"));
  const Result r = mcref("validate " + quote(path("suite.toml")) + " -o " + quote(path("out")) +
                         " --case 'tau_*' --case other --quiet");
  EXPECT_NE(r.exit_code, 2) << r.err;
  EXPECT_TRUE(fs::exists(path("out/tables/tau_a.h5")));
  EXPECT_TRUE(fs::exists(path("out/tables/other.h5")));
  fs::remove_all(path("out"));
  fs::create_directories(path("out"));
  const Result one = mcref("validate " + quote(path("suite.toml")) + " -o " + quote(path("out")) + " --case tau_b --quiet");
  EXPECT_NE(one.exit_code, 2) << one.err;
  EXPECT_TRUE(fs::exists(path("out/tables/tau_b.h5")));
  EXPECT_FALSE(fs::exists(path("out/tables/tau_a.h5")));
  EXPECT_FALSE(fs::exists(path("out/tables/other.h5")));
  const Result none = mcref("validate " + quote(path("suite.toml")) + " -o " + quote(path("out")) + " --case 'nope*' --quiet");
  EXPECT_EQ(none.exit_code, 2);
  ASSERT_EQ(lines(none.err).size(), 1u) << none.err;
  for (const char* piece : {"--case", "nope*", "tau_a, tau_b, other"})
    EXPECT_NE(none.err.find(piece), std::string::npos) << none.err;
  // A mistyped pattern beside one that matches is refused too (it dropped its cases silently).
  const Result mixed = mcref("validate " + quote(path("suite.toml")) + " -o " + quote(path("out2")) +
                             " --case tau_b --case 'zzz*' --quiet");
  EXPECT_EQ(mixed.exit_code, 2) << mixed.err;
  expect_one_line_error(mixed, {"--case", "'zzz*' matches no case"});
  EXPECT_FALSE(fs::exists(path("out2")));
}

// validate reuses a case's cached tables when their simulation fingerprint
// and configuration match this build's, whatever the commit; a different
// fingerprint, none (an older mcref) or another configuration simulates again.
TEST_F(Cli, ValidateReusesTablesOnlyWithTheSameSimFingerprint) {
  write("x.toml", experiment());
  write("suite.toml", "[suite]\nname = \"s\"\n[[case]]\nname = \"tau\"\nexperiment = \"x.toml\"\n");
  const std::string table = path("out/tables/tau.h5");
  auto validate = [&] {
    const Result r = mcref("validate " + quote(path("suite.toml")) + " -o " + quote(path("out")));
    EXPECT_NE(r.exit_code, 2) << r.err;
    return r.err.find("(cached tables)") != std::string::npos;
  };
  // Rewrites the cached file with its provenance changed by `edit`.
  auto rewrite = [&](void (*edit)(mcref::Provenance&)) {
    mcref::TableFile f = mcref::read_table_file(table);
    edit(f.provenance);
    mcref::write_table_file(table, f);
  };
  EXPECT_FALSE(validate()) << "nothing to reuse yet";
  EXPECT_EQ(mcref::read_table_file(table).provenance.sim_fingerprint, mcref::mcref_sim_fingerprint());
  EXPECT_TRUE(validate()) << "same build, same config: reused";
  rewrite([](mcref::Provenance& p) { p.git_commit = "0123456789ab-dirty"; });
  EXPECT_TRUE(validate()) << "another commit, same fingerprint: reused";
  rewrite([](mcref::Provenance& p) { p.sim_fingerprint = "0000000000000000"; });
  EXPECT_FALSE(validate()) << "another fingerprint: simulated again";
  EXPECT_EQ(mcref::read_table_file(table).provenance.sim_fingerprint, mcref::mcref_sim_fingerprint());
  rewrite([](mcref::Provenance& p) { p.sim_fingerprint.clear(); });
  EXPECT_FALSE(validate()) << "no fingerprint (an older file): simulated again";
  EXPECT_TRUE(validate());
  write("x.toml", experiment("tau0 = 0.4\nbeta = 0.8\n"));
  EXPECT_FALSE(validate()) << "another configuration: simulated again";
}

// validate on 1 and 2 threads gives the same tables (sums, squares and kept
// batch values, bit for bit) and the same results.json but for the command
// line: the simulations and the model checks, including a model with Monte
// Carlo noise of its own (volumetric_mc) and the micrograin models' parallel
// quadrature.
TEST_F(Cli, ValidateGivesTheSameTablesAndResultsOnAnyThreadCount) {
  const std::string src = std::string(MCREF_SOURCE_DIR) + "/validate/experiments/";
  write("suite.toml",
        "[suite]\nname = \"s\"\n"
        "[[case]]\nname = \"slab\"\nexperiment = \"" + src + "slab_single_layer.toml\"\n"
        "set = [\"run.batches=3\", \"measure.0.samples=300\"]\n"
        "[[case]]\nname = \"grains\"\nexperiment = \"" + src + "micrograin_brdf_diffuse.toml\"\n"
        "set = [\"run.batches=3\", \"geometry.tile=40\", \"measure.0.samples=300\", \"measure.1.samples=300\",\n"
        "  \"measure.0.theta_i_deg=[30]\", \"measure.0.theta_o_bins=3\", \"measure.0.phi_bins=3\", \"measure.1.theta_i_deg=[30]\"]\n"
        "[[case]]\nname = \"spheres\"\nexperiment = \"" + src + "spheres_packing.toml\"\n"
        "set = [\"run.batches=3\", \"geometry.tile=20\", \"measure.0.samples=300\"]\n"
        "[[case.check]]\ntable = \"brdf\"\nmodel = \"volumetric_mc\"\n");
  std::string results[2];
  std::vector<mcref::TableFile> files[2];
  for (int threads : {1, 2}) {
    const std::string out = path("out" + std::to_string(threads));
    const Result r = shell("SOURCE_DATE_EPOCH=1 " + quote(MCREF_BINARY) + " validate " + quote(path("suite.toml")) + " -o " +
                           quote(out) + " --quiet --threads " + std::to_string(threads));
    ASSERT_TRUE(r.exit_code == 0 || r.exit_code == 1) << r.err;
    // The command line (--threads) is the one thing allowed to differ: its value is cut out.
    std::string json = slurp(out + "/results.json");
    for (std::size_t at = 0; (at = json.find("\"command_line\": \"", at)) != std::string::npos;) {
      at += std::string("\"command_line\": \"").size();
      json.erase(at, json.find('"', at) - at);
    }
    results[threads - 1] = json;
    for (const char* c : {"slab", "grains", "spheres"})
      files[threads - 1].push_back(mcref::read_table_file(out + "/tables/" + c + ".h5"));
  }
  EXPECT_FALSE(results[0].empty());
  EXPECT_TRUE(results[0] == results[1]) << "results.json differs on 1 and 2 threads";
  for (std::size_t c = 0; c < files[0].size(); ++c) {
    ASSERT_EQ(files[0][c].tables.size(), files[1][c].tables.size());
    EXPECT_EQ(files[0][c].provenance.config, files[1][c].provenance.config);
    for (std::size_t t = 0; t < files[0][c].tables.size(); ++t) {
      const mcref::Table &a = files[0][c].tables[t], &b = files[1][c].tables[t];
      EXPECT_FALSE(a.batch_values.empty()) << a.name;
      // Bit for bit (a NaN, a batch without samples, equals itself).
      const auto same = [](const std::vector<double>& x, const std::vector<double>& y) {
        return x.size() == y.size() && std::memcmp(x.data(), y.data(), x.size() * sizeof(double)) == 0;
      };
      EXPECT_TRUE(same(a.sum, b.sum)) << a.name;
      EXPECT_TRUE(same(a.sum_sq, b.sum_sq)) << a.name;
      EXPECT_TRUE(same(a.batch_values, b.batch_values)) << a.name;
    }
  }
}

// Messages show the value as given: a number just past a bound in full, not
// rounded into the range; a value of the wrong type with what it is.
TEST_F(Cli, ErrorsShowTheValueAsGiven) {
  expect_rejected(experiment("tau0 = 0.5\nbeta = 100.0000001\n"), {"bad.toml", "geometry.beta", "100.0000001", "(0, 100]"});
  expect_rejected(experiment("tau0 = 0.5\nbeta = true\n"), {"bad.toml", "geometry.beta", "not true"});
  expect_rejected(experiment("tau0 = 0.5\nbeta = 0.8\n", "", "quantity = \"tau_plus\"\ntheta_i_deg = [30]\nsamples = 2.5\n"),
                  {"bad.toml", "measure.0.samples", "not 2.5"});
  expect_rejected(experiment("tau0 = 0.5\nbeta = 0.8\n", "", "quantity = \"tau_plus\"\ntheta_i_deg = [30, \"a\"]\nsamples = 100\n"),
                  {"bad.toml", "measure.0.theta_i_deg", "not the string \"a\""});
}

// A single-valued option given twice is refused, not silently taken from the last.
TEST_F(Cli, SingleValuedOptionsGivenTwiceAreRefused) {
  const std::string exp = write("good.toml", experiment());
  const std::string out = quote(path("a.h5")), other = quote(path("b.h5"));
  for (const std::string& twice : {"-o " + out + " -o " + other, "-o " + out + " --output " + other,
                                   "-o " + out + " --threads 1 --threads 2", "-o " + out + " --seed 1 --seed 2"}) {
    const Result r = mcref("simulate " + quote(exp) + " " + twice + " --quiet");
    EXPECT_EQ(r.exit_code, 2) << twice;
    EXPECT_NE(r.err.find("is given twice"), std::string::npos) << r.err;
  }
  EXPECT_TRUE(stray({"good.toml"}).empty());
}

// What a verb prints on stdout must be written: a full device is an error.
TEST_F(Cli, StdoutThatCannotBeWrittenIsAnError) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  const std::string exp = write("good.toml", experiment());
  const std::string out = path("good.h5");
  ASSERT_EQ(mcref("simulate " + quote(exp) + " -o " + quote(out) + " --quiet").exit_code, 0);
  const auto to_full = [&](const std::string& args) {  // (in a subshell: the fixture redirects stdout after it)
    return shell("(" + quote(MCREF_BINARY) + " " + args + " > /dev/full)");
  };
  const Result info = to_full("info " + quote(out));
  EXPECT_EQ(info.exit_code, 3);
  EXPECT_NE(info.err.find("standard output"), std::string::npos) << info.err;
  EXPECT_EQ(to_full("--version").exit_code, 3);
  EXPECT_EQ(shell("(" + quote(MCREF_BINARY) + " info " + quote(out) + " > /dev/null)").exit_code, 0);  // (written: 0)
}
