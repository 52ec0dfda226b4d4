#include "validate/report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
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

std::string html(const std::string& s) {
  std::string o;
  for (char c : s) {
    if (c == '<') o += "&lt;";
    else if (c == '>') o += "&gt;";
    else if (c == '&') o += "&amp;";
    else o += c;
  }
  return o;
}

std::string results_json(const Suite& suite, const std::vector<CaseResult>& results) {
  std::ostringstream j;
  j << "{\n  \"suite\": " << json_string(suite.name) << ",\n  \"title\": " << json_string(suite.title)
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
        << ", \"p_value\": " << json_number(m.p_value) << ", \"max_abs_z\": " << json_number(m.max_abs_z)
        << ", \"max_rel_error\": " << json_number(m.max_rel_error) << ", \"rms_rel_error\": " << json_number(m.rms_rel_error)
        << ",\n        \"model_values\": [";
      for (std::size_t v = 0; v < r.model_values.size(); ++v) j << (v ? ", " : "") << json_number(r.model_values[v]);
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
    j << "]}" << (k + 1 < results.size() ? "," : "") << "\n";
  }
  j << "  ]\n}\n";
  return j.str();
}

const char* kStyle =
    "body{font-family:sans-serif;max-width:1100px;margin:2em auto;color:#222}"
    "table{border-collapse:collapse;font-size:13px}td,th{border:1px solid #ccc;padding:3px 6px;text-align:left}"
    ".pass{color:#070}.FAIL{color:#b00;font-weight:bold}.measured{color:#555}"
    "img{max-width:100%;border:1px solid #eee}pre{background:#f6f6f6;padding:6px;font-size:12px;overflow-x:auto}";

// The error budget of a case: per model, what its single-scattering terms get
// wrong and what the single-scattering assumption leaves out (ErrorBudget).
std::string budget_html(const std::vector<ErrorBudget>& budget) {
  std::ostringstream h;
  h << "<p>Where the albedo error of each approximate model comes from (mean of the RGB channels it is compared "
    << "on; &Delta; = model &minus; sim, in % of the simulated albedo): &Delta;<sub>total</sub> = "
    << "&Delta;<sub>order 1</sub> (its single-scattering terms: masking, shadowing, pore visibility, against the "
    << "simulated order 1) &minus; the simulated orders &ge; 2 (the single-scattering assumption).</p>\n"
    << "<table><tr><th>model</th><th>&theta;<sub>i</sub> (deg)</th><th>sim albedo</th><th>model</th>"
    << "<th>&Delta;<sub>total</sub></th><th>&Delta;<sub>order 1</sub> (masking)</th>"
    << "<th>&minus;orders &ge; 2 (single scattering)</th></tr>\n";
  std::string model;  // "model on table"
  double masking = 0, single = 0;
  auto summary = [&]() {
    if (model.empty()) return;
    char row[320];
    std::snprintf(row, sizeof row,
                  "<tr><td colspan='7'><i>%s: of the summed |&Delta;| over &theta;<sub>i</sub>, %.0f %% from its "
                  "masking terms and %.0f %% from the single-scattering assumption</i></td></tr>\n",
                  html(model).c_str(), 100 * masking / std::max(1e-300, masking + single),
                  100 * single / std::max(1e-300, masking + single));
    h << row;
  };
  for (const ErrorBudget& b : budget) {
    if (b.model + " on " + b.table != model) {
      summary();
      model = b.model + " on " + b.table;
      masking = single = 0;
    }
    masking += std::fabs(b.order1_error);
    single += std::fabs(b.multiple);
    const double pct = b.sim != 0 ? 100 / b.sim : NAN;
    char row[320];
    std::snprintf(row, sizeof row,
                  "<td>%.1f</td><td>%.4f &plusmn; %.4f</td><td>%.4f</td><td>%+.1f %%</td><td>%+.1f %%</td>"
                  "<td>%+.1f %%</td>",
                  b.theta_i * 180 / 3.14159265358979323846, b.sim, b.sim_stderr, b.model_value,
                  (b.model_value - b.sim) * pct, b.order1_error * pct, -b.multiple * pct);
    h << "<tr><td>" << html(b.model) << " <small>(" << html(b.table) << ")</small></td>" << row << "</tr>\n";
  }
  summary();
  h << "</table>\n";
  return h.str();
}

std::string report_html(const Suite& suite, const std::vector<CaseResult>& results, bool have_plots) {
  std::ostringstream h;
  int fails = 0, passes = 0, measured = 0;
  for (const CaseResult& c : results)
    for (const CheckResult& r : c.checks)
      (r.verdict.status == "FAIL" ? fails : r.verdict.status == "pass" ? passes : measured)++;
  h << "<!doctype html><html><head><meta charset='utf-8'><title>" << html(suite.title) << "</title><style>" << kStyle
    << "</style></head><body>\n<h1>" << html(suite.title) << "</h1>\n";
  h << "<p>Suite <code>" << html(suite.file) << "</code>: " << passes << " checks pass, " << fails << " fail, "
    << measured << " approximate models measured. Exact models (a Poisson field makes them exact) must agree within "
    << "the standard errors: chi-squared p &ge; " << suite.significance
    << " and every |z| under the Sidak bound at the same level; a failure there means the simulator or the model "
    << "code is wrong. Approximate models get their error measured, and fail only past a tolerance the suite states. "
    << "z = (sim - model)/stderr, mapped from Student's t (batches - 1 dof) to a normal quantile. "
    << "Max rel. error is over cells where |sim| &gt; 5 stderr. Caveat: the cells of one table share each "
    << "realization of the geometry, so they are positively correlated, while the &chi;&sup2; test treats them as "
    << "independent; with few batches this makes false failures of exact models more likely than the stated level "
    << "(suites use many small batches to keep it close).</p>\n";
  h << "<h2>Summary</h2>\n<table><tr><th>case</th><th>figure</th><th>table</th><th>model</th><th>kind</th>"
    << "<th>cells</th><th>&chi;&sup2;/dof</th><th>max |z|</th><th>max rel. error</th><th>verdict</th></tr>\n";
  char buf[64];
  for (const CaseResult& c : results)
    for (const CheckResult& r : c.checks) {
      const Comparison& m = r.comparison;
      h << "<tr><td><a href='#" << html(c.name) << "'>" << html(c.name) << "</a></td><td>" << html(c.figure) << "</td><td>"
        << html(r.table) << "</td><td>" << html(r.model) << "</td><td>" << (r.exact ? "exact" : "approximate")
        << "</td><td>" << m.cells << "</td>";
      std::snprintf(buf, sizeof buf, "<td>%.3g</td><td>%.2f</td><td>%.3g</td>", m.chi2_per_dof(), m.max_abs_z, m.max_rel_error);
      h << buf << "<td class='" << r.verdict.status << "'>" << r.verdict.status << "</td></tr>\n";
    }
  h << "</table>\n";
  for (const CaseResult& c : results) {
    h << "<h2 id='" << html(c.name) << "'>" << html(c.name) << (c.figure.empty() ? "" : " &mdash; " + html(c.figure))
      << "</h2>\n<p>" << html(c.description) << "</p>\n";
    if (have_plots) h << "<img src='plots/" << html(c.name) << ".png' alt='" << html(c.name) << "'>\n";
    if (!c.energy.empty()) {
      h << "<p>Energy by scattering order (channel 0, first azimuth of incidence; delta lobes included):</p>\n"
        << "<table><tr><th>table</th><th>&theta;<sub>i</sub> (deg)</th><th>energy</th><th>order 1</th>"
        << "<th>orders &ge; 2</th><th>share of multiple scattering</th></tr>\n";
      for (const EnergyShare& e : c.energy) {
        char row[256];
        std::snprintf(row, sizeof row, "<td>%.1f</td><td>%.4f</td><td>%.4f</td><td>%.4f</td><td>%.1f %%</td>",
                      e.theta_i * 180 / 3.14159265358979323846, e.total, e.single, e.multiple,
                      e.total > 0 ? 100 * e.multiple / e.total : 0.0);
        h << "<tr><td>" << html(e.table) << "</td>" << row << "</tr>\n";
      }
      h << "</table>\n";
    }
    if (!c.budget.empty()) h << budget_html(c.budget);
    h << "<ul>\n";
    for (const CheckResult& r : c.checks)
      h << "<li><b>" << html(r.model) << "</b> on <code>" << html(r.table) << "</code> (" << (r.exact ? "exact" : "approximate")
        << "): <span class='" << r.verdict.status << "'>" << r.verdict.status << "</span> &mdash; " << html(r.verdict.reason)
        << "<br><small>" << html(r.model_description) << "</small></li>\n";
    h << "</ul>\n<details><summary>provenance</summary><pre>tables: " << html(c.table_file)
      << (c.reused ? " (reused from cache)" : "") << "\nmcref " << html(c.provenance.mcref_version) << ", commit "
      << html(c.provenance.git_commit) << ", created " << html(c.provenance.created) << ", seed " << c.provenance.seed
      << "\ncommand: " << html(c.provenance.command_line) << "\n\n" << html(c.provenance.config) << "</pre></details>\n";
  }
  h << "</body></html>\n";
  return h.str();
}

}  // namespace

void write_report(const Suite& suite, const std::vector<CaseResult>& results, const SuiteOptions& o) {
  const fs::path out(o.out_dir);
  write_text_file((out / "results.json").string(), results_json(suite, results));
  // Plots: Debian's python3 with matplotlib and h5py (see scripts/setup.sh).
  const fs::path script = fs::path(o.scripts_dir) / "plot_validation.py";
  bool have_plots = false;
  if (fs::exists(script)) {
    const std::string cmd = "/usr/bin/python3 '" + script.string() + "' '" + out.string() + "'" + (o.quiet ? " --quiet" : "");
    have_plots = std::system(cmd.c_str()) == 0;
    if (!have_plots) std::fprintf(stderr, "mcref validate: warning: plotting failed (%s); the report has no plots\n", cmd.c_str());
  } else {
    std::fprintf(stderr, "mcref validate: warning: %s not found; the report has no plots\n", script.c_str());
  }
  write_text_file((out / "report.html").string(), report_html(suite, results, have_plots));
  int fails = 0, total = 0;
  for (const CaseResult& c : results)
    for (const CheckResult& r : c.checks) {
      ++total;
      if (r.verdict.status == "FAIL") {
        ++fails;
        std::fprintf(stderr, "FAIL %s: %s vs %s: %s\n", c.name.c_str(), r.table.c_str(), r.model.c_str(), r.verdict.reason.c_str());
      }
    }
  std::fprintf(stderr, "mcref validate: %zu cases, %d checks, %d failed; report: %s\n", results.size(), total, fails,
               (out / "report.html").c_str());
}

}  // namespace mcref
