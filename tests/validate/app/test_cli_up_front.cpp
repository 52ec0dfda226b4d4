// Runs that cannot succeed are refused before any work (issue #20, items 6
// and 10): a suite check of a table the experiment does not write, or of a
// model that does not predict that table; tables that would not fit in
// memory; and a dataset's declared size costs nothing until its entries are
// computed.
#include "tests/validate/app/cli_fixture.h"

using namespace mcref_test;

namespace {

// A suite of two cases: a valid first one (simulated first, were the checks
// found late) and the second, of `experiment`, with `check`.
std::string suite(const std::string& check, const std::string& experiment = "x.toml") {
  return "[suite]\nname = \"s\"\n\n"
         "[[case]]\nname = \"good\"\nexperiment = \"x.toml\"\n\n"
         "[[case]]\nname = \"second\"\nexperiment = \"" + experiment + "\"\n\n"
         "[[case.check]]\n" + check;
}

const char* kMeasures =
    "quantity = \"tau_plus\"\ntheta_i_deg = [30]\nsamples = 2000\n\n"
    "[[measure]]\nquantity = \"g1\"\ntheta_i_deg = [30]\ntheta_m_bins = 4\nphi_m_bins = 4\nsamples = 2000\n";

}  // namespace

TEST_F(Cli, ImpossibleSuiteChecksAreRefusedBeforeAnyCaseIsSimulated) {
  write("x.toml", experiment("tau0 = 0.5\nbeta = 0.8\n", "", kMeasures));
  write("aniso.toml", experiment("tau0 = 0.5\nbeta_x = 0.5\nbeta_y = 1.0\n", "", kMeasures));
  write("rough.toml", experiment("tau0 = 0.5\nbeta = 1.0\n[material.grain]\ntype = \"rough_conductor\"\npreset = \"copper\"\nalpha = 0.4\n"
                                 "[material.base]\ntype = \"conductor\"\npreset = \"gold\"\n",
                                 "", "quantity = \"brdf\"\ntheta_i_deg = [30]\nsamples = 200\n"));
  struct Bad {
    std::string check, experiment;
    std::vector<std::string> expected;
  };
  const std::vector<Bad> bad{
      // A model of another quantity: tau_plus_eq22 on the g1 table.
      {"table = \"g1\"\nmodel = \"tau_plus_eq22\"\n", "x.toml",
       {"s.toml", "case.1.check.0", "case \"second\"", "model \"tau_plus_eq22\"", "table \"g1\"",
        "predicts tau_plus tables of micrograin geometry, and table g1 is g1"}},
      // A model of another geometry kind.
      {"table = \"tau_plus\"\nmodel = \"chandrasekhar_isotropic\"\n", "x.toml",
       {"s.toml", "case.1.check.0", "chandrasekhar_isotropic", "predicts brdf tables of slab geometry"}},
      // A table no measure writes, though its name starts like one (tau_plus_).
      {"table = \"tau_plus_albedo\"\nmodel = \"tau_plus_eq22\"\n", "x.toml",
       {"s.toml", "case.1.check.0", "table \"tau_plus_albedo\" is not written", "it writes: tau_plus, g1, g1_conditional"}},
      // A model whose assumption the case breaks: anisotropic grains.
      {"table = \"g1\"\nmodel = \"g1_smith_series_n4\"\n", "aniso.toml",
       {"s.toml", "case.1.check.0", "g1_smith_series_n4", "isotropic grains only"}},
      // Rough-conductor grains, for which the grain term has no form (it gave 0).
      {"table = \"brdf_order1_grain\"\nmodel = \"gdist_grain_union\"\n", "rough.toml",
       {"s.toml", "case.1.check.0", "gdist_grain_union", "no grain term for rough_conductor grains"}},
  };
  for (const Bad& b : bad) {
    write("s.toml", suite(b.check, b.experiment));
    const Result r = mcref("validate " + quote(path("s.toml")) + " -o " + quote(path("out")) + " --quiet");
    EXPECT_EQ(r.exit_code, 2) << r.err;
    expect_one_line_error(r, b.expected);
    EXPECT_FALSE(fs::exists(path("out"))) << "the output directory was written: a case ran before the check";
    fs::remove_all(path("out"));
  }
  // The same checks on tables the cases do write run.
  write("s.toml", suite("table = \"g1\"\nmodel = \"g1_exact_tau_plus\"\n", "aniso.toml"));
  const Result ok = mcref("validate " + quote(path("s.toml")) + " -o " + quote(path("out")) + " --quiet");
  EXPECT_LE(ok.exit_code, 1) << ok.err;
  EXPECT_TRUE(fs::exists(path("out/results.json")));
}

TEST_F(Cli, TablesTooLargeForMemoryAreRefusedWithTheirSize) {
  // 10^4 x 10^4 bins (each allowed): 1.8e9 cells of micrograin brdf tables.
  const std::string huge =
      "quantity = \"brdf\"\ntheta_i_deg = [30]\ntheta_o_bins = 10000\nphi_bins = 10000\nsamples = 1000\n";
  const std::string material = "\n[material.grain]\ntype = \"lambertian\"\n[material.base]\ntype = \"lambertian\"\n";
  std::string exp = experiment("tau0 = 0.5\nbeta = 0.8\n", "", huge);
  exp.insert(exp.find("[run]"), material);
  expect_rejected(exp, {"bad.toml", "measure.0.theta_o_bins", "measure.0.phi_bins", "GB of memory", "1.8e+09 cells",
                        "more than the budget"});
  // The budget is MCREF_MEMORY_LIMIT when set: a small run refused under 1 MB,
  // and a malformed value named.
  const std::string small = write("small.toml", experiment());
  write("th.toml", experiment("tau0 = 0.5\nbeta = 0.8\n", "",
                              "quantity = \"tau_height\"\ntheta_i_deg = [0, 10, 20, 30, 40, 50, 60, 70, 80, 85]\n"
                              "phi_i_deg = [0, 10, 20, 30, 40, 50, 60, 70, 80, 90]\nh_points = 4000\nsamples = 10\n"));
  const Result tiny = shell("MCREF_MEMORY_LIMIT=1M " + quote(MCREF_BINARY) + " simulate " + quote(path("th.toml")) +
                            " -o " + quote(path("o.h5")) + " --quiet");
  expect_one_line_error(tiny, {"th.toml", "measure.0.h_points", "budget of 1 MB (MCREF_MEMORY_LIMIT)"});
  EXPECT_EQ(tiny.exit_code, 2);
  const Result bad = shell("MCREF_MEMORY_LIMIT=lots " + quote(MCREF_BINARY) + " simulate " + quote(small) + " -o " +
                           quote(path("o.h5")) + " --quiet");
  expect_one_line_error(bad, {"MCREF_MEMORY_LIMIT", "lots"});
  EXPECT_FALSE(fs::exists(path("o.h5")));
  // The same refusal from validate, before the first case runs.
  write("big.toml", exp);
  write("x.toml", experiment());
  write("s.toml", "[suite]\nname = \"s\"\n[[case]]\nname = \"a\"\nexperiment = \"x.toml\"\n"
                  "[[case]]\nname = \"b\"\nexperiment = \"big.toml\"\n");
  const Result v = mcref("validate " + quote(path("s.toml")) + " -o " + quote(path("out")) + " --quiet");
  expect_one_line_error(v, {"big.toml", "measure.0.theta_o_bins", "GB"});
  EXPECT_FALSE(fs::exists(path("out")));
  // validate's tables keep their batch values, and the up-front check counts them:
  // th.toml's 4e5 cells need about 20 MB, and 200 MB more with 64 batches' values.
  write("s.toml", "[suite]\nname = \"s\"\n[[case]]\nname = \"a\"\nexperiment = \"x.toml\"\n"
                  "[[case]]\nname = \"b\"\nexperiment = \"th.toml\"\nset = [\"run.batches=64\"]\n");
  const Result kept = shell("MCREF_MEMORY_LIMIT=100M " + quote(MCREF_BINARY) + " validate " + quote(path("s.toml")) +
                            " -o " + quote(path("out")) + " --quiet");
  EXPECT_EQ(kept.exit_code, 2);
  expect_one_line_error(kept, {"s.toml", "case \"b\"", "th.toml", "budget of 100 MB (MCREF_MEMORY_LIMIT)"});
  EXPECT_FALSE(fs::exists(path("out"))) << "case a ran before case b's tables were found too large";
  // Without the batch values the same tables fit that budget.
  const Result plain = shell("MCREF_MEMORY_LIMIT=100M " + quote(MCREF_BINARY) + " simulate " + quote(path("th.toml")) +
                             " -o " + quote(path("o.h5")) + " --quiet --set run.batches=64");
  EXPECT_EQ(plain.exit_code, 0) << plain.err;
}

// The largest dataset allowed (2^40 entries) starts at once and holds only
// what it computes: two entries with --stop-after 2, then resumes. (Planning
// every entry first took 3 GB and 40 s per 10^6 entries: this would not end.)
TEST_F(Cli, HugeDatasetsPlanTheirEntriesLazily) {
  write("base.toml", experiment());
  write("ds.toml", "[dataset]\nexperiment = \"base.toml\"\nentries = 1099511627776\nseed = 5\n\n"
                   "[[parameter]]\nkey = \"geometry.tau0\"\nrange = [0.2, 0.8]\n");
  const std::string run = "timeout 120 " + quote(MCREF_BINARY) + " dataset " + quote(path("ds.toml")) + " -o " +
                          quote(path("d.h5")) + " --threads 1 --stop-after 2";
  const Result first = shell(run);
  ASSERT_EQ(first.exit_code, 0) << first.err;
  EXPECT_NE(first.err.find("1099511627776 entries (2 simulated, 0 resumed)"), std::string::npos) << first.err;
  EXPECT_TRUE(fs::exists(path("d.h5.parts/entry-0.h5")));
  EXPECT_TRUE(fs::exists(path("d.h5.parts/entry-1.h5")));
  const Result second = shell(run);
  ASSERT_EQ(second.exit_code, 0) << second.err;
  EXPECT_NE(second.err.find("(2 simulated, 2 resumed)"), std::string::npos) << second.err;
  EXPECT_TRUE(fs::exists(path("d.h5.parts/entry-3.h5")));
  EXPECT_FALSE(fs::exists(path("d.h5")));
  // A sampled range reaching past what the key allows is refused before anything is written.
  write("bad.toml", "[dataset]\nexperiment = \"base.toml\"\nentries = 1099511627776\nseed = 5\n\n"
                    "[[parameter]]\nkey = \"geometry.tau0\"\nrange = [0.5, 1.5]\n");
  const Result bad = shell("timeout 120 " + quote(MCREF_BINARY) + " dataset " + quote(path("bad.toml")) + " -o " +
                           quote(path("b.h5")) + " --stop-after 50");
  EXPECT_EQ(bad.exit_code, 2) << bad.err;
  expect_one_line_error(bad, {"bad.toml: key 'geometry.tau0': 1.5 (the upper end of range)", "= 1.5 is out of range; allowed (0, 1)"});
  EXPECT_FALSE(fs::exists(path("b.h5.parts")));
}

// Every value a dataset's parameters can take is checked before any work,
// whichever entries this run computes: a bad grid value or choice that only
// later entries (--stop-after) or another shard's entries would meet, and the
// ends of a sampled range. (Before, only the entries a run computed were
// checked: the bad value failed a later run, after hours of work.)
TEST_F(Cli, EveryParameterValueIsCheckedBeforeAnyEntry) {
  write("base.toml", experiment("tau0 = 0.5\nbeta = 0.8\n", "", "quantity = \"tau_plus\"\ntheta_i_deg = [30]\nsamples = 200\n"));
  struct Case {
    std::string parameters, options;
    std::vector<std::string> expected;
  };
  const std::vector<Case> cases{
      // The last of a grid's values, with --stop-after 1: entries 0 and 1 are fine.
      {"key = \"geometry.tau0\"\nvalues = [0.3, 0.5, 1.25]\n", "--stop-after 1",
       {"ds.toml: key 'geometry.tau0': 1.25 (values)", "other parameters as in entry 0", "= 1.25 is out of range; allowed (0, 1)"}},
      // A bad value met only by the other shard's entries (entry 1 of 2).
      {"key = \"geometry.tau0\"\nvalues = [0.3, 2.5]\n", "--shard 0/2",
       {"ds.toml: key 'geometry.tau0': 2.5 (values)", "= 2.5 is out of range; allowed (0, 1)"}},
      // A bad choice, whichever entry 0 draws.
      {"key = \"geometry.tau0\"\nchoices = [0.4, -0.1]\n", "--stop-after 1",
       {"ds.toml: key 'geometry.tau0': -0.1 (choices)", "= -0.1 is out of range; allowed (0, 1)"}},
      // The upper end of a log-uniform range.
      {"key = \"geometry.beta\"\nrange = [0.5, 200.0]\ndistribution = \"log_uniform\"\n", "--stop-after 1",
       {"ds.toml: key 'geometry.beta': 200 (the upper end of range)", "= 200 is out of range; allowed (0, 100]"}},
  };
  for (const Case& c : cases) {
    write("ds.toml", "[dataset]\nexperiment = \"base.toml\"\nentries = 1\nseed = 5\n\n[[parameter]]\n" + c.parameters);
    const Result r = mcref("dataset " + quote(path("ds.toml")) + " -o " + quote(path("d.h5")) + " --threads 1 --quiet " + c.options);
    EXPECT_EQ(r.exit_code, 2) << c.parameters << r.err;
    expect_one_line_error(r, c.expected);
    EXPECT_FALSE(fs::exists(path("d.h5.parts"))) << c.parameters;
    EXPECT_FALSE(fs::exists(path("d.h5"))) << c.parameters;
  }
  // The same datasets with the bad value mended run (entry 0 is fine in each).
  for (const Case& c : cases) {
    std::string parameters = c.parameters;
    for (const auto& [from, to] : std::vector<std::pair<std::string, std::string>>{{"1.25", "0.75"}, {"2.5", "0.25"}, {"-0.1", "0.1"}, {"200.0", "20.0"}})
      if (const auto at = parameters.find(from); at != std::string::npos) parameters.replace(at, from.size(), to);
    write("ds.toml", "[dataset]\nexperiment = \"base.toml\"\nentries = 1\nseed = 5\n\n[[parameter]]\n" + parameters);
    const Result r = mcref("dataset " + quote(path("ds.toml")) + " -o " + quote(path("d.h5")) + " --threads 1 --quiet " + c.options);
    EXPECT_EQ(r.exit_code, 0) << parameters << r.err;
    fs::remove_all(path("d.h5"));
    fs::remove_all(path("d.h5.parts"));
  }
}

// A case's name names its table file and plots (tables/<name>.h5): an empty
// name, "." or ".." (which wrote tables/.h5, tables/..h5) are refused up front.
TEST_F(Cli, CaseNamesThatMakeNoFileNameAreRefused) {
  write("x.toml", experiment());
  for (const std::string name : {"", ".", "..", ".hidden"}) {
    write("s.toml", "[suite]\nname = \"s\"\n\n[[case]]\nname = \"" + name + "\"\nexperiment = \"x.toml\"\n");
    const Result r = mcref("validate " + quote(path("s.toml")) + " -o " + quote(path("out")) + " --quiet");
    EXPECT_EQ(r.exit_code, 2) << "name \"" << name << "\": " << r.err;
    expect_one_line_error(r, {"s.toml", "case.0.name", "must be non-empty and not start with '.'"});
    EXPECT_FALSE(fs::exists(path("out"))) << "name \"" << name << "\"";
    fs::remove_all(path("out"));
  }
}

// A case whose experiment is bad is named, with the experiment's own file and
// key: cases may share an experiment file and differ only in their `set`s.
TEST_F(Cli, SuiteErrorsNameTheCase) {
  write("x.toml", experiment());
  write("s.toml", "[suite]\nname = \"s\"\n\n[[case]]\nname = \"good\"\nexperiment = \"x.toml\"\n\n"
                  "[[case]]\nname = \"dense\"\nexperiment = \"x.toml\"\nset = [\"geometry.tau0=1.5\"]\n");
  const Result r = mcref("validate " + quote(path("s.toml")) + " -o " + quote(path("out")) + " --quiet");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  expect_one_line_error(r, {"s.toml: key 'case.1': case \"dense\": ", "x.toml", "geometry.tau0", "= 1.5 is out of range; allowed (0, 1)"});
  EXPECT_FALSE(fs::exists(path("out")));
}

// Suite-level mistakes are refused, naming where they are: an included
// suite asking for another significance (every case is judged at the top
// suite's), a missing include (with the suite that names it), `tolerance = 0`
// (absent means measured; 0 would read as exact), the same check twice, and
// a check's own key with its index.
TEST_F(Cli, SuiteMistakesAreRefusedWhereTheyAre) {
  write("x.toml", experiment());
  const std::string inner = "[suite]\nname = \"in\"\nsignificance = 0.01\n[[case]]\nname = \"a\"\nexperiment = \"x.toml\"\n";
  write("in.toml", inner);
  struct Case {
    std::string suite;
    std::vector<std::string> pieces;
  };
  const std::string head = "[suite]\nname = \"s\"\n";
  const std::string other = "[[case]]\nname = \"b\"\nexperiment = \"x.toml\"\n";
  const std::vector<Case> cases{
      {head + "include = [\"in.toml\"]\n" + other, {"s.toml", "suite.significance", "in.toml", "significance = 0.01"}},
      {head + "include = [\"gone.toml\"]\n" + other, {"gone.toml", "s.toml", "suite.include"}},
      {head + other + "[[case.check]]\ntable = \"tau_plus\"\nmodel = \"tau_plus_eq22\"\ntolerance = 0\n",
       {"s.toml", "case.0.check.0.tolerance", "= 0"}},
      {head + other + "[[case.check]]\ntable = \"tau_plus\"\nmodel = \"tau_plus_eq22\"\n"
                      "[[case.check]]\ntable = \"tau_plus\"\nmodel = \"tau_plus_eq22\"\n",
       {"s.toml", "case.0.check.1.model", "already checked on table \"tau_plus\""}},
      {head + other + "[[case.check]]\ntable = \"tau_plus\"\nmodel = \"tau_plus_eq22\"\n"
                      "[[case.check]]\ntable = \"tau_plus\"\nmodel = \"no_such_model\"\n",
       {"s.toml", "case.0.check.1.model", "\"no_such_model\" is not a known model"}},
  };
  for (const Case& c : cases) {
    write("s.toml", c.suite);
    const Result r = mcref("validate " + quote(path("s.toml")) + " -o " + quote(path("out")) + " --quiet");
    EXPECT_EQ(r.exit_code, 2) << c.suite << r.err;
    expect_one_line_error(r, c.pieces);
    EXPECT_FALSE(fs::exists(path("out"))) << c.suite;
  }
  // The same significance in both is accepted.
  write("s.toml", head + "significance = 0.01\ninclude = [\"in.toml\"]\n" + other);
  const Result ok = mcref("validate " + quote(path("s.toml")) + " -o " + quote(path("out")) + " --quiet");
  EXPECT_LE(ok.exit_code, 1) << ok.err;
}
