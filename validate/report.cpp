#include "validate/report.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "sim/files/temp_file.h"
#include "validate/suite.h"

namespace fs = std::filesystem;

namespace mcref {

namespace {

std::string json_string(const std::string& s) {
  std::string o = "\"";
  for (char c : s) {
    switch (c) {
      case '"': o += "\\\""; break;
      case '\\': o += "\\\\"; break;
      case '\n': o += "\\n"; break;
      case '\t': o += "\\t"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char b[8];
          std::snprintf(b, sizeof b, "\\u%04x", c);
          o += b;
        } else {
          o += c;
        }
    }
  }
  return o + "\"";
}

std::string json_number(double v) {
  if (!std::isfinite(v)) return "null";
  char b[32];
  std::snprintf(b, sizeof b, "%.10g", v);
  return b;
}

std::string results_json(const Suite& suite, const std::vector<CaseResult>& results) {
  std::ostringstream j;
  j << "{\n  \"suite\": " << json_string(suite.name) << ",\n  \"file\": " << json_string(suite.file)
    << ",\n  \"title\": " << json_string(suite.title)
    << ",\n  \"significance\": " << json_number(suite.significance) << ",\n  \"cases\": [\n";
  for (std::size_t k = 0; k < results.size(); ++k) {
    const CaseResult& c = results[k];
    j << "    {\"name\": " << json_string(c.name) << ", \"figure\": " << json_string(c.figure)
      << ", \"description\": " << json_string(c.description) << ", \"tables\": " << json_string(c.table_file)
      << ",\n     \"checks\": [\n";
    for (std::size_t i = 0; i < c.checks.size(); ++i) {
      const CheckResult& r = c.checks[i];
      const Comparison& m = r.comparison;
      j << "       {\"table\": " << json_string(r.table) << ", \"quantity\": " << json_string(r.quantity)
        << ", \"model\": " << json_string(r.model) << ", \"exact\": " << (r.exact ? "true" : "false")
        << ", \"description\": " << json_string(r.model_description) << ", \"tolerance\": " << json_number(r.tolerance)
        << ", \"status\": " << json_string(r.verdict.status) << ", \"reason\": " << json_string(r.verdict.reason)
        << ", \"cells\": " << m.cells << ", \"chi2_per_dof\": " << json_number(m.chi2_per_dof())
        << ", \"p_value\": " << json_number(m.p_value) << ", \"joint_test\": " << json_string(m.joint_test)
        << ", \"effective_dof\": " << json_number(m.effective_dof)
        << ", \"max_abs_z\": " << json_number(m.max_abs_z)
        << ", \"max_rel_error\": " << json_number(m.max_rel_error) << ", \"rms_rel_error\": " << json_number(m.rms_rel_error);
      const ModelAccuracy& a = r.accuracy;
      if (a.integrals > 0)
        j << ",\n        \"rule_accuracy\": {\"target\": " << json_number(a.target) << ", \"integrals\": " << a.integrals
          << ", \"unconverged\": " << a.unconverged << ", \"worst_rel_error\": " << json_number(a.worst_error)
          << ", \"worst_cell\": " << a.worst_cell << "}";
      j << ",\n        \"model_values\": [";
      for (std::size_t v = 0; v < r.model_values.size(); ++v) j << (v ? ", " : "") << json_number(r.model_values[v]);
      j << "],\n        \"z\": [";
      for (std::size_t v = 0; v < m.z.size(); ++v) j << (v ? ", " : "") << json_number(m.z[v]);
      j << "]}" << (i + 1 < c.checks.size() ? "," : "") << "\n";
    }
    j << "     ],\n     \"error_budget\": [";
    for (std::size_t i = 0; i < c.budget.size(); ++i) {
      const ErrorBudget& b = c.budget[i];
      j << (i ? ",\n       " : "\n       ") << "{\"table\": " << json_string(b.table) << ", \"model\": " << json_string(b.model)
        << ", \"theta_i\": " << json_number(b.theta_i) << ", \"sim\": " << json_number(b.sim)
        << ", \"sim_stderr\": " << json_number(b.sim_stderr) << ", \"model_value\": " << json_number(b.model_value)
        << ", \"order1_error\": " << json_number(b.order1_error) << ", \"multiple\": " << json_number(b.multiple) << "}";
    }
    j << "],\n     \"energy\": [";
    for (std::size_t i = 0; i < c.energy.size(); ++i) {
      const EnergyShare& e = c.energy[i];
      j << (i ? ",\n       " : "\n       ") << "{\"table\": " << json_string(e.table)
        << ", \"theta_i\": " << json_number(e.theta_i) << ", \"phi_i\": " << json_number(e.phi_i)
        << ", \"total\": " << json_number(e.total) << ", \"single\": " << json_number(e.single)
        << ", \"multiple\": " << json_number(e.multiple) << "}";
    }
    const Provenance& p = c.provenance;
    // Provenance as stored with the tables: the same whether they were simulated or reused.
    j << "],\n     \"provenance\": {\"mcref_version\": "
      << json_string(p.mcref_version) << ", \"git_commit\": " << json_string(p.git_commit)
      << ", \"created\": " << json_string(p.created) << ", \"seed\": " << p.seed
      << ", \"command_line\": " << json_string(p.command_line) << ", \"config\": " << json_string(p.config) << "}}"
      << (k + 1 < results.size() ? "," : "") << "\n";
  }
  j << "  ]\n}\n";
  return j.str();
}

}  // namespace

void write_results(const Suite& suite, const std::vector<CaseResult>& results, const SuiteOptions& o) {
  const fs::path out(o.out_dir);
  write_text_file((out / "results.json").string(), results_json(suite, results));
  int pass = 0, fail = 0, measured = 0, not_applicable = 0;
  for (const CaseResult& c : results)
    for (const CheckResult& r : c.checks) {
      const std::string& s = r.verdict.status;
      (s == "pass" ? pass : s == "FAIL" ? fail : s == "n/a" ? not_applicable : measured)++;
      if (s == "FAIL")
        std::fprintf(stderr, "FAIL %s: %s vs %s: %s\n", c.name.c_str(), r.table.c_str(), r.model.c_str(), r.verdict.reason.c_str());
    }
  std::fprintf(stderr, "mcref validate: %zu cases, %d checks: %d pass, %d FAIL, %d measured, %d n/a; results: %s\n",
               results.size(), pass + fail + measured + not_applicable, pass, fail, measured, not_applicable,
               (out / "results.json").c_str());
  if (!o.quiet) {
    // The plots and the report are rendered from results.json and the tables,
    // without simulating (scripts/run.sh does both after validating).
    const fs::path scripts(o.scripts_dir);
    std::fprintf(stderr, "render the plots and the report (OUTDIR/report.html) with:\n  /usr/bin/python3 %s %s && /usr/bin/python3 %s %s\n",
                 (scripts / "plot_validation.py").c_str(), out.c_str(), (scripts / "report.py").c_str(), out.c_str());
  }
}

}  // namespace mcref
