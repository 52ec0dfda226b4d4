# scripts/report.py: the report rendered from a real (tiny) validation run,
# without simulating again. The run (tests/scripts/report_suite/, ~10 s) has an
# exact model that passes and an all-zero delta table against a model without
# a delta lobe ("n/a"). Its figures come from scripts/plot_validation.py.
# ctest sets MCREF_BINARY and MCREF_SOURCE_DIR (CMakeLists.txt, scripts.pytest).
import html
import json
import os
import re
import shutil
import subprocess
import sys
import tomllib

import pytest

SOURCE_DIR = os.environ.get("MCREF_SOURCE_DIR", os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..")))
BINARY = os.environ.get("MCREF_BINARY", os.path.join(SOURCE_DIR, "build", "mcref"))
SCRIPTS = os.path.join(SOURCE_DIR, "scripts")
PYTHON = "/usr/bin/python3"
sys.path.insert(0, SCRIPTS)

from figure_slug import figure_slug  # noqa: E402


def run(*args):
    p = subprocess.run(list(args), capture_output=True, text=True)
    return p.returncode, p.stdout, p.stderr


@pytest.fixture(scope="module")
def run_dir(tmp_path_factory):
    """A validation run of the tiny suite, its plots and its report."""
    out = str(tmp_path_factory.mktemp("validate") / "out")
    code, _, err = run(BINARY, "validate", os.path.join(SOURCE_DIR, "tests/scripts/report_suite/suite.toml"),
                       "-o", out, "--threads", "2")
    assert code == 0, err
    assert "render the plots and the report" in err and "report.py" in err  # validate says how to render
    code, _, err = run(PYTHON, os.path.join(SCRIPTS, "plot_validation.py"), out, "--quiet")
    assert code == 0, err
    code, _, err = run(PYTHON, os.path.join(SCRIPTS, "report.py"), out, "--quiet")
    assert code == 0, err
    return out


@pytest.fixture
def copy_of(run_dir, tmp_path):
    """A copy of the run to change and render again."""
    out = str(tmp_path / "out")
    shutil.copytree(run_dir, out)
    return out


def results(out):
    with open(os.path.join(out, "results.json")) as f:
        return json.load(f)


def page(out):
    with open(os.path.join(out, "report.html"), encoding="utf-8") as f:
        return f.read()


def render(out):
    code, _, err = run(PYTHON, os.path.join(SCRIPTS, "report.py"), out, "--quiet")
    assert code == 0, err
    return page(out)


def test_headline_counts_match_the_results(run_dir):
    checks = [c for case in results(run_dir)["cases"] for c in case["checks"]]
    count = {s: sum(c["status"] == s for c in checks) for s in ("pass", "FAIL", "measured", "n/a")}
    # The suite is built to have passes, measured and n/a checks in distinct numbers.
    assert count["n/a"] >= 1 and len({count["pass"], count["measured"], count["n/a"]}) == 3, count
    text = re.sub(r"\s+", " ", re.sub(r"<[^>]+>", "", page(run_dir)))
    assert (f"{len(checks)} checks: {count['pass']} pass, {count['FAIL']} FAIL, {count['measured']} measured, "
            f"{count['n/a']} n/a") in text


def test_summary_has_one_row_per_model(run_dir):
    models = {c["model"] for case in results(run_dir)["cases"] for c in case["checks"]}
    summary = page(run_dir).split('id="summary"')[1].split("<details")[0]
    rows = re.findall(r"<tr><td title=\"[^\"]*\"><code>([^<]+)</code>", summary)
    assert sorted(rows) == sorted(models)
    per_check = page(run_dir).split('id="checks"')[1].split("</details>")[0]
    assert per_check.count("<tr>") == 1 + sum(len(case["checks"]) for case in results(run_dir)["cases"])


def test_relative_error_is_coloured_for_approximate_models_only(run_dir):
    summary = page(run_dir).split('id="summary"')[1].split("<details")[0]
    rows = re.findall(r"<tr><td title=\"[^\"]*\"><code>[^<]+</code></td><td>(exact|approximate)</td>(.*?)</tr>",
                      summary, re.S)
    kinds = {kind for kind, _ in rows}
    assert kinds == {"exact", "approximate"}, kinds  # the tiny suite has both
    coloured = 0
    for kind, cells in rows:
        style, text = re.findall(r'style="background: ([^"]*)">([^<]*)</td>', cells)[-1]
        if kind == "exact" or text == "–":  # exact, or no relative error (all its checks n/a)
            assert style == "", (kind, cells)
        else:
            assert style.startswith("hsl("), (kind, cells)
            coloured += 1
    assert coloured >= 1


def test_every_plot_of_a_case_is_embedded_and_figure_plots_are_indexed(copy_of):
    plots = os.path.join(copy_of, "plots")
    first = sorted(os.listdir(plots))[0]
    case = results(copy_of)["cases"][0]
    shutil.copy(os.path.join(plots, first), os.path.join(plots, case["name"] + "_lobes.png"))
    figure_plot = f"figure_{figure_slug(case['figure'])}.png"
    shutil.copy(os.path.join(plots, first), os.path.join(plots, figure_plot))
    text = render(copy_of)
    for f in os.listdir(plots):
        if f != figure_plot:
            assert f'<img src="plots/{f}"' in text, f
    index = text.split('id="figures"')[1].split('id="not-reproduced"')[0]
    assert f'<img src="plots/{figure_plot}"' in index
    section = text.split(f'id="case-{case["name"]}"')[1].split("<h3")[0]
    assert f'<img src="plots/{case["name"]}_lobes.png"' in section


def test_figure_index_lists_cases_and_the_figures_not_reproduced(run_dir):
    text = page(run_dir)
    index = text.split('id="figures"')[1]
    for case in results(run_dir)["cases"]:
        assert f"<h3>{html.escape(case['figure'])}</h3>" in index
        assert f'<a href="#case-{case["name"]}">' in index
    with open(os.path.join(SOURCE_DIR, "validate/figures_not_reproduced.toml"), "rb") as f:
        missing = tomllib.load(f)["figure"]
    table = index.split('id="not-reproduced"')[1].split("</table>")[0]
    assert table.count("<tr>") == 1 + len(missing)
    for row in missing:
        assert row["reason"] in html.unescape(table)


def test_renders_again_without_tables(copy_of):
    shutil.rmtree(os.path.join(copy_of, "tables"))
    os.remove(os.path.join(copy_of, "report.html"))
    assert "n/a" in render(copy_of)


def test_bad_input_names_the_file_and_writes_nothing(tmp_path):
    code, _, err = run(PYTHON, os.path.join(SCRIPTS, "report.py"), str(tmp_path))
    assert code != 0 and "results.json" in err
    (tmp_path / "results.json").write_text("{not json")
    code, _, err = run(PYTHON, os.path.join(SCRIPTS, "report.py"), str(tmp_path))
    assert code != 0 and "not valid JSON" in err
    assert sorted(os.listdir(tmp_path)) == ["results.json"]


def test_figure_slug():
    assert figure_slug("LRPB23 Fig. 5") == "lrpb23_fig_5"
    assert figure_slug("d'Eon Fig. 2, Fig. 5, Eq. 40") == "d_eon_fig_2_fig_5_eq_40"
    assert figure_slug("SpongeCake Eq. 11-12, 16 (anisotropic)") == "spongecake_eq_11_12_16_anisotropic"


# Loads the page in Debian's chromium (scripts/setup.sh installs it), headless,
# with a probe injected before anything else in a copy of the page: it records
# script errors, console.error calls, resources that fail to load and images
# that do not decode, and writes them into the page once loaded, which
# --dump-dom prints. Chromium's own log is not used: it does not report broken
# images, and its format changes between versions.
PROBE = """<script>
window.__probe = [];
window.addEventListener("error", function (e) {
  var t = e.target;
  window.__probe.push(t && t !== window && t.getAttribute ? "failed to load: " + t.getAttribute("src") : "error: " + e.message);
}, true);
console.error = function () { window.__probe.push("console.error: " + Array.prototype.join.call(arguments, " ")); };
window.addEventListener("load", function () {
  document.querySelectorAll("img").forEach(function (img) {
    if (!img.complete || img.naturalWidth === 0) window.__probe.push("image not shown: " + img.getAttribute("src"));
  });
  var pre = document.createElement("pre");
  pre.textContent = "PROBE-RESULT " + JSON.stringify(window.__probe);
  document.body.appendChild(pre);
});
</script>"""


def browser_problems(out, tmp_path, page_text=None):
    """What the probe saw when chromium loaded OUTDIR's report (a list of strings)."""
    chromium = shutil.which("chromium")
    assert chromium, "chromium is missing: run scripts/setup.sh"
    probed = os.path.join(out, "probed_report.html")
    with open(probed, "w", encoding="utf-8") as f:
        f.write((page_text or page(out)).replace("<head>", "<head>" + PROBE, 1))
    p = subprocess.run([chromium, "--headless", "--no-sandbox", "--disable-gpu", f"--user-data-dir={tmp_path}/profile",
                        "--virtual-time-budget=20000", "--dump-dom", "file://" + os.path.abspath(probed)],
                       capture_output=True, text=True, timeout=300)
    found = re.findall(r"PROBE-RESULT (\[.*\])</pre>", p.stdout)
    assert found, f"chromium did not finish loading the page (exit {p.returncode}): {p.stderr[-2000:]}"
    return json.loads(html.unescape(found[-1]))


def test_chromium_loads_the_report_without_errors(copy_of, tmp_path):
    assert browser_problems(copy_of, tmp_path) == []
    assert any(f.endswith(".png") for f in os.listdir(os.path.join(copy_of, "plots")))


def test_chromium_probe_sees_errors(copy_of, tmp_path):
    # The probe is not blind: a broken image and a script error are reported.
    plots = os.path.join(copy_of, "plots")
    broken = sorted(os.listdir(plots))[0]
    with open(os.path.join(plots, broken), "wb") as f:
        f.write(b"not a png")
    text = page(copy_of).replace("</body>", "<script>undefined_function();</script></body>")
    problems = browser_problems(copy_of, tmp_path, text)
    assert f"image not shown: plots/{broken}" in problems
    assert any(p.startswith("error:") and "undefined_function" in p for p in problems)
