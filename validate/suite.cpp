#include "validate/suite.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>

#include <tbb/global_control.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "sim/experiment/simulate.h"
#include "sim/experiment/table_plan.h"
#include "sim/experiment/toml_reader.h"
#include "sim/files/input_file.h"
#include "sim/hdf5/table_file.h"
#include "sim/parallel/progress.h"
#include "sim/tally/brdf_tally.h"
#include "validate/metrics.h"
#include "validate/model_evaluation.h"
#include "validate/report.h"
#include "validate/suite_outputs.h"

namespace fs = std::filesystem;

namespace mcref {

namespace {
Suite load_suite_at_depth(const std::string& path, int depth, const std::string& from_file);
}  // namespace

Suite load_suite(const std::string& path) { return load_suite_at_depth(path, 0, ""); }

namespace {

// from_file: the suite that includes this one (its suite.include names it).
Suite load_suite_at_depth(const std::string& path, int depth, const std::string& from_file) {
  if (depth > 8) throw ConfigError(path, "suite.include", "includes nest deeper than 8 (a cycle?)");
  const std::string text = read_input_file(path, from_file, from_file.empty() ? "" : "suite.include");
  toml::table root;
  try {
    root = toml::parse(text, path);
  } catch (const toml::parse_error& e) {
    throw ConfigError(path, "", "TOML syntax error at line " + std::to_string(e.source().begin.line) + ": " +
                                    std::string(e.description()));
  }
  Suite s;
  s.file = path;
  s.files = {path};
  TomlReader r(root, path, "");
  const toml::table* head = r.table("suite");
  if (!head) r.fail("suite", "is required ([suite] with name)");
  TomlReader h(*head, path, "suite");
  s.name = h.any_string("name");
  s.title = h.any_string("title", s.name);
  s.significance = h.number("significance", {0, 0.5, true, true}, 1e-3);
  s.significance_given = h.has("significance");
  const std::vector<std::string> includes = h.strings("include");
  h.finish();
  const fs::path dir = fs::path(path).parent_path();
  // Cases of included suites (paths relative to this file) come first.
  for (const std::string& inc : includes) {
    const Suite other = load_suite_at_depth((dir / inc).string(), depth + 1, path);
    // Every case is judged at the top suite's significance: an included suite
    // asking for another one would be silently overruled.
    if (other.significance_given && other.significance != s.significance)
      h.fail("significance", "= " + exact_text(s.significance) + (s.significance_given ? "" : " (not given: the default)") +
                                 " judges every case, the included ones' too, and the included " + other.file +
                                 " sets significance = " + exact_text(other.significance) + "; give both the same value");
    s.files.insert(s.files.end(), other.files.begin(), other.files.end());
    for (const Case& c : other.cases) {
      for (const Case& have : s.cases)
        if (have.name == c.name) throw ConfigError(path, "suite.include", "case \"" + c.name + "\" appears twice");
      s.cases.push_back(c);
    }
  }
  const auto cases = r.tables("case");
  if (cases.empty()) r.fail("case", "at least one [[case]] is required");
  for (std::size_t i = 0; i < cases.size(); ++i) {
    TomlReader c(*cases[i], path, "case." + std::to_string(i));
    Case k;
    k.file = path;
    k.key = "case." + std::to_string(i);
    k.name = c.any_string("name");
    for (const Case& other : s.cases)
      if (other.name == k.name) c.fail("name", "\"" + k.name + "\" is used twice");
    if (k.name.find_first_of("/\\ ") != std::string::npos) c.fail("name", "must not contain '/', '\\' or spaces");
    if (k.name.empty() || k.name.front() == '.')  // (it names tables/<name>.h5 and the plots)
      c.fail("name", "\"" + k.name + "\" must be non-empty and not start with '.'");
    k.figure = c.any_string("figure", "");
    k.description = c.any_string("description", "");
    k.experiment_path = (dir / c.any_string("experiment")).string();
    k.sets = c.strings("set");
    const auto checks = c.tables("check");
    for (std::size_t j = 0; j < checks.size(); ++j) {
      TomlReader cr(*checks[j], path, c.full("check." + std::to_string(j)));
      Check chk;
      chk.table = cr.any_string("table");
      chk.model = cr.any_string("model");
      const ModelInfo* m = find_model(chk.model);
      if (!m) cr.fail("model", "\"" + chk.model + "\" is not a known model");
      // Absent: the approximate model is measured, not judged (0 would read as "exact agreement").
      chk.tolerance = cr.number("tolerance", {0, 1e6, true, false}, 0.0);
      if (m->exact && chk.tolerance > 0)
        cr.fail("tolerance", "is not allowed for an exact model (it must agree within its standard errors)");
      for (const Check& have : k.checks)
        if (have.table == chk.table && have.model == chk.model)
          cr.fail("model", "\"" + chk.model + "\" is already checked on table \"" + chk.table + "\" in this case");
      cr.finish();
      k.checks.push_back(chk);
    }
    c.finish();
    s.cases.push_back(k);
  }
  r.finish();
  return s;
}

// Cached tables are current when the build that simulated them had this
// build's simulation fingerprint (scripts/sim_fingerprint.cmake: the sources
// sim/ reaches, the mcref version, compiler, flags and library versions) and
// the same effective configuration (seed included), and they hold every
// checked table. The commit is not compared: a change to validate/, to the
// analytic models only validate uses, or to the report, committed or not, keeps
// the tables; a file without a fingerprint (older mcref) is simulated again.
bool cache_is_current(const TableFile& cached, const Experiment& ex, const Case& c) {
  const Provenance& p = cached.provenance;
  if (p.sim_fingerprint.empty() || p.sim_fingerprint != mcref_sim_fingerprint() || p.config != ex.text ||
      p.seed != ex.run.seed)
    return false;
  for (const Check& chk : c.checks)
    if (!cached.find(chk.table)) return false;
  return true;
}

// Loads cached tables if current, else simulates and writes them.
TableFile tables_for(const Case& c, const Experiment& ex, const SuiteOptions& o, const std::string& path,
                     std::size_t k, std::size_t n, bool& reused) {
  reused = false;
  TableFile cached;
  if (o.ranks->root() && !o.force && fs::exists(path)) {
    try {
      cached = read_table_file(path);
      reused = cache_is_current(cached, ex, c);
    } catch (const std::exception&) {
      // unreadable or foreign: simulate again and replace it
    }
  }
  std::string verdict = reused ? "reuse" : "";  // rank 0's, for every rank
  o.ranks->broadcast(verdict);
  reused = !verdict.empty();
  if (reused) return cached;
  SimulateOptions so;
  so.threads = o.threads;
  so.quiet = o.quiet;
  so.ranks = o.ranks;
  so.label = "[" + std::to_string(k + 1) + "/" + std::to_string(n) + "] " + c.name;
  so.keep_batch_values = true;  // the verdicts estimate the cells' correlation from them
  TableFile f;
  f.tables = simulate(ex, so);
  if (!o.ranks->root()) return f;  // the tables are complete on rank 0 only
  // In name order, as a cached file lists them: the report and results.json
  // come out the same whether the tables were simulated or reused.
  std::sort(f.tables.begin(), f.tables.end(), [](const Table& a, const Table& b) { return a.name < b.name; });
  f.provenance = make_provenance(ex.text, ex.file, ex.run.seed, o.command_line);
  write_table_file(path, f);
  return f;
}

// Energy by order from the albedo tables (components attribute lists the
// component names, "total" last); first azimuth of incidence, channel 0.
std::vector<EnergyShare> energy_shares(const TableFile& f) {
  std::vector<EnergyShare> out;
  for (const Table& t : f.tables) {
    const auto names_it = t.attributes.find("components");
    if (names_it == t.attributes.end() || t.axes.size() != 4 || t.name.size() < 7 ||
        t.name.compare(t.name.size() - 7, 7, "_albedo") != 0)
      continue;
    std::vector<std::string> names;
    std::stringstream ss(names_it->second);
    for (std::string n; std::getline(ss, n, ',');) names.push_back(n);
    const std::size_t nc = t.axes[2].size(), nch = t.axes[3].size(), nphi = t.axes[1].size();
    if (names.size() != nc) continue;
    for (std::size_t a = 0; a < t.axes[0].size(); ++a) {
      EnergyShare e;
      e.table = t.name;
      e.theta_i = t.axes[0].values[a];
      e.phi_i = t.axes[1].values[0];
      for (std::size_t c = 0; c < nc; ++c) {
        const double v = t.value(((a * nphi + 0) * nc + c) * nch + 0);
        if (names[c] == "total") e.total = v;
        else if (names[c].rfind("order1", 0) == 0) e.single += v;
        else e.multiple += v;
      }
      out.push_back(e);
    }
  }
  return out;
}

// Error budgets of the checks on albedo tables whose order-1 components the
// model predicts (see ErrorBudget).
std::vector<ErrorBudget> error_budgets(const TableFile& f, const std::vector<CheckResult>& checks) {
  std::vector<ErrorBudget> out;
  for (const CheckResult& r : checks) {
    const Table* t = f.find(r.table);
    if (!t || r.quantity != "albedo" || is_delta_table(r.table) || t->axes.size() != 4 || t->attributes.count("components") == 0)
      continue;
    std::vector<std::string> names;
    std::stringstream ss(t->attributes.at("components"));
    for (std::string n; std::getline(ss, n, ',');) names.push_back(n);
    const std::size_t nc = t->axes[2].size(), nch = t->axes[3].size(), nphi = t->axes[1].size();
    if (names.size() != nc || names.back() != "total") continue;
    const std::vector<double> v = t->values(), se = t->stderrs();
    for (std::size_t a = 0; a < t->axes[0].size(); ++a) {
      ErrorBudget b;
      b.table = r.table;
      b.model = r.model;
      b.theta_i = t->axes[0].values[a];
      int channels = 0;
      for (std::size_t k = 0; k < nch; ++k) {
        auto at = [&](std::size_t c) { return ((a * nphi + 0) * nc + c) * nch + k; };
        bool predicted = std::isfinite(r.model_values[at(nc - 1)]);
        double order1 = 0, multiple = 0;
        for (std::size_t c = 0; c + 1 < nc; ++c) {
          if (names[c].rfind("order1", 0) == 0) {
            predicted = predicted && std::isfinite(r.model_values[at(c)]);
            order1 += r.model_values[at(c)] - v[at(c)];
          } else {
            multiple += v[at(c)];
          }
        }
        if (!predicted) continue;
        ++channels;
        b.sim += v[at(nc - 1)];
        b.sim_stderr += se[at(nc - 1)];
        b.model_value += r.model_values[at(nc - 1)];
        b.order1_error += order1;
        b.multiple += multiple;
      }
      if (channels == 0) break;  // the model does not predict the order-1 parts
      for (double* x : {&b.sim, &b.sim_stderr, &b.model_value, &b.order1_error, &b.multiple}) *x /= channels;
      out.push_back(b);
    }
  }
  return out;
}

// A grey material makes the RGB channels of a table bit-identical: counting
// them three times would triple the chi-squared. A channel whose sums equal an
// earlier channel's in every cell is left out (model value NaN).
void exclude_duplicate_channels(const Table& t, std::vector<double>& model) {
  if (t.axes.empty() || t.axes.back().name != "channel") return;
  const std::size_t nch = t.axes.back().size(), rows = t.cells() / nch;
  for (std::size_t k = 1; k < nch; ++k)
    for (std::size_t j = 0; j < k; ++j) {
      bool same = true;
      for (std::size_t r = 0; r < rows && same; ++r)
        same = t.sum[r * nch + k] == t.sum[r * nch + j] && t.sum_sq[r * nch + k] == t.sum_sq[r * nch + j] &&
               (model[r * nch + k] == model[r * nch + j] || (std::isnan(model[r * nch + k]) && std::isnan(model[r * nch + j])));
      if (!same) continue;
      for (std::size_t r = 0; r < rows; ++r) model[r * nch + k] = NAN;
      break;
    }
}

// The checks of a case on its tables (simulated, or the empty tables its
// experiment will write): the suite's, or else every model that predicts a
// table (of its component, if the model names one) and applies to the
// experiment.
std::vector<Check> checks_of(const Case& c, const std::vector<Table>& tables, const Experiment& ex) {
  if (!c.checks.empty()) return c.checks;
  std::vector<Check> checks;
  for (const Table& t : tables)
    for (const ModelInfo& m : models_for(t.quantity, ex.kind)) {
      if (!m.component.empty() && (t.attributes.count("component") == 0 || t.attributes.at("component") != m.component))
        continue;
      if (model_mismatch(m.name, t, ex).empty()) checks.push_back({t.name, m.name, 0.0});
    }
  return checks;
}

// One model against one simulated table.
CheckResult run_check(const Check& chk, const Table& t, const Experiment& ex, const Suite& suite) {
  const ModelInfo* info = find_model(chk.model);
  CheckResult r;
  r.table = chk.table;
  r.quantity = t.quantity;
  r.model = chk.model;
  r.exact = info->exact;
  r.model_description = info->description;
  r.tolerance = chk.tolerance;
  {
    const ModelAccuracyScope scope(&r.accuracy);
    r.model_values = evaluate_model(chk.model, t, ex);
  }
  exclude_duplicate_channels(t, r.model_values);
  const std::vector<double> model_se = evaluate_model_stderr(chk.model, t, ex, r.model_values);
  static const std::vector<double> none;  // (a table read from a file without batch values)
  r.comparison = compare(t.values(), t.stderrs(), r.model_values, t.batches, model_se, t.channels(),
                         t.has_batch_values() ? t.batch_values : none);
  r.verdict = judge(r.comparison, info->exact, suite.significance, chk.tolerance);
  settle_joint_test(r.comparison, suite.significance);
  return r;
}

// A table cell's position, e.g. "theta_i 0.5236, phi_i 0, theta_o [1.48, 1.571]"
// (the channel and component axes left out: a model's integral spans them).
std::string describe_cell(const Table& t, std::size_t flat) {
  std::string out;
  for (std::size_t d = t.axes.size(); d-- > 0;) {
    const Axis& a = t.axes[d];
    const std::size_t i = flat % a.size();
    flat /= a.size();
    if (a.name == "channel" || a.name == "component") continue;
    char b[96];
    if (a.kind == Axis::Kind::Bins)
      std::snprintf(b, sizeof b, "%s [%.4g, %.4g]", a.name.c_str(), a.lower(i), a.upper(i));
    else
      std::snprintf(b, sizeof b, "%s %.4g", a.name.c_str(), a.values[i]);
    out = b + (out.empty() ? "" : ", " + out);
  }
  return out;
}

// One line for a case whose model integrals stopped above their error target
// (ModelAccuracy), naming the worst; "" if there are none.
std::string accuracy_warning(const std::string& label, const std::vector<CheckResult>& checks, const TableFile& f) {
  std::size_t cells = 0, affected = 0;
  const CheckResult* worst = nullptr;
  for (const CheckResult& r : checks) {
    if (r.accuracy.unconverged == 0) continue;
    cells += r.accuracy.unconverged;
    ++affected;
    if (!worst || r.accuracy.worst_error > worst->accuracy.worst_error) worst = &r;
  }
  if (!worst) return "";
  const ModelAccuracy& a = worst->accuracy;
  char b[160];
  std::snprintf(b, sizeof b, "%zu integral%s of %zu check%s stopped at the rule's limit above the %.3g relative target",
                cells, cells == 1 ? "" : "s", affected, affected == 1 ? "" : "s", a.target);
  char e[32];
  std::snprintf(e, sizeof e, "%.3g", a.worst_error);
  return "warning: " + label + ": " + b + "; worst: " + worst->model + " on " + worst->table + ", cell " +
         describe_cell(*f.find(worst->table), a.worst_cell) + ", relative error " + e +
         " (results.json: rule_accuracy)\n";
}

}  // namespace

// The checks are judged on the tables the experiments will write, known from
// their measures (empty_tables), so nothing is simulated first.
std::vector<Experiment> plan_suite(const Suite& suite, int threads) {
  std::vector<Experiment> experiments;
  for (const Case& c : suite.cases) {
    // The experiment's own errors name its file and key; which case is given too
    // (cases may share an experiment, with other `set`s).
    try {
      experiments.push_back(load_experiment(c.experiment_path, c.sets));
      check_memory(experiments.back(), threads, /*keep_batch_values=*/true);  // as run_case simulates
    } catch (const ConfigError& e) {
      throw ConfigError(c.file, c.key, "case \"" + c.name + "\": " + e.what());
    }
  }
  for (std::size_t k = 0; k < suite.cases.size(); ++k) {
    const Case& c = suite.cases[k];
    const Experiment& ex = experiments[k];
    const std::vector<Table> tables = table_outline(ex);
    for (std::size_t j = 0; j < c.checks.size(); ++j) {
      const Check& chk = c.checks[j];
      const std::string key = c.key + ".check." + std::to_string(j);
      const auto t = std::find_if(tables.begin(), tables.end(), [&](const Table& x) { return x.name == chk.table; });
      if (t == tables.end()) {
        std::string names;
        for (const Table& x : tables) names += (names.empty() ? "" : ", ") + x.name;
        throw ConfigError(c.file, key, "case \"" + c.name + "\": table \"" + chk.table + "\" is not written by " +
                                           ex.file + " (it writes: " + names + ")");
      }
      const std::string why = model_mismatch(chk.model, *t, ex);
      if (!why.empty())
        throw ConfigError(c.file, key, "case \"" + c.name + "\": model \"" + chk.model + "\" cannot be checked on table \"" +
                                           chk.table + "\": " + why);
    }
  }
  return experiments;
}

int run_suite(const Suite& suite, const SuiteOptions& o) {
  // --threads bounds the model checks as well as the simulations.
  const int threads = o.threads > 0 ? o.threads : tbb::info::default_concurrency();
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  // Validate every case's experiment and checks before simulating anything.
  const std::vector<Experiment> experiments = plan_suite(suite, o.threads);
  check_on_root(*o.ranks, [&] { check_suite_outputs(suite, experiments, o.out_dir); });
  if (o.ranks->root()) fs::create_directories(fs::path(o.out_dir) / "tables");
  std::vector<CaseResult> results;
  int failures = 0;
  // Under MPI the other ranks wait (asleep) in the next case's reuse verdict
  // while rank 0 checks this one: an error here must end the job, not leave
  // them waiting.
  const DistributedStep step;
  for (std::size_t k = 0; k < suite.cases.size(); ++k) {
    const Case& c = suite.cases[k];
    const Experiment& ex = experiments[k];
    CaseResult cr;
    cr.name = c.name;
    cr.figure = c.figure;
    cr.description = c.description;
    cr.table_file = (fs::path("tables") / (c.name + ".h5")).string();
    const TableFile f = tables_for(c, ex, o, (fs::path(o.out_dir) / cr.table_file).string(), k, suite.cases.size(), cr.reused);
    if (!o.ranks->root()) continue;  // the other ranks only help simulate
    cr.provenance = f.provenance;
    cr.energy = energy_shares(f);
    const std::vector<Check> checks = checks_of(c, f.tables, ex);
    for (const Check& chk : checks)
      if (!f.find(chk.table)) throw std::runtime_error("table " + chk.table + " missing from " + cr.table_file);
    // The checks of a case are independent: evaluated in parallel, kept in order.
    // Progress counts table cells: those a long evaluator reports as it goes,
    // and at the end of each check the rest of its table.
    double cells = 0;
    for (const Check& chk : checks) cells += static_cast<double>(f.find(chk.table)->cells());
    Progress progress("[" + std::to_string(k + 1) + "/" + std::to_string(suite.cases.size()) + "] " + c.name + " models",
                      cells, o.quiet);
    std::mutex progress_lock;
    cr.checks.resize(checks.size());
    tbb::parallel_for(std::size_t{0}, checks.size(), [&](std::size_t i) {
      // Isolated, so that a thread waiting inside one check (on a model's
      // cache lock, or for its nested parallel loops) never starts another.
      const Table& table = *f.find(checks[i].table);
      std::size_t reported = 0;  // cells of this check already counted
      const auto count = [&](std::size_t n) {
        const std::lock_guard<std::mutex> lock(progress_lock);
        n = std::min(n, table.cells() - reported);
        reported += n;
        progress.advance(static_cast<double>(n));
      };
      {
        const CellProgressScope scope(count);
        tbb::this_task_arena::isolate([&] { cr.checks[i] = run_check(checks[i], table, ex, suite); });
      }
      count(table.cells());
    });
    progress.finish();
    if (!o.quiet) std::fputs(accuracy_warning("case " + c.name, cr.checks, f).c_str(), stderr);
    for (const CheckResult& r : cr.checks) failures += r.verdict.status == "FAIL";
    cr.budget = error_budgets(f, cr.checks);
    results.push_back(std::move(cr));
    if (!o.quiet) {
      int bad = 0;
      for (const CheckResult& r : results.back().checks) bad += r.verdict.status == "FAIL";
      std::fprintf(stderr, "[%zu/%zu] %-34s %s%s\n", k + 1, suite.cases.size(), c.name.c_str(),
                   bad ? "FAIL" : "ok", results.back().reused ? " (cached tables)" : "");
    }
  }
  if (o.ranks->root()) write_results(suite, results, o);
  return failures;
}

}  // namespace mcref
