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

import plot_manifest  # noqa: E402
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


def first_png(plots):
    return sorted(f for f in os.listdir(plots) if f.endswith(".png"))[0]


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


def test_smallest_p_is_given_and_coloured_for_exact_models_and_their_chi2_is_not(copy_of):
    # One check of the exact model (p1_eq10) given p = 0.002: between the significance (0.001,
    # red) and 0.05 (green), so its colour is neither; its smallest p is that check's.
    r = results(copy_of)
    exact = [c for case in r["cases"] for c in case["checks"] if c["exact"] and c["status"] == "pass"]
    assert len(exact) >= 2
    exact[1]["p_value"] = 0.002
    with open(os.path.join(copy_of, "results.json"), "w") as f:
        json.dump(r, f)
    render(copy_of)
    summary = page(copy_of).split('id="summary"')[1].split("<details")[0]
    rows = re.findall(r"<tr><td title=\"[^\"]*\"><code>([^<]+)</code></td><td>(exact|approximate)</td>(.*?)</tr>",
                      summary, re.S)
    seen = set()
    for model, kind, cells in rows:
        (p_style, p_text), (chi2_style, chi2_text) = re.findall(r'style="background: ([^"]*)">([^<]*)</td>', cells)[:2]
        if kind == "exact" and model == exact[1]["model"]:
            assert p_text == "0.002" and chi2_text != "–", cells
            hue = int(re.match(r"hsl\((\d+),", p_style).group(1))
            assert 0 < hue < 120, p_style
            assert chi2_style == "", cells
            seen.add(kind)
        elif kind == "approximate" and chi2_text != "–":
            assert p_text == "–" and p_style == "" and chi2_style.startswith("hsl("), cells
            seen.add(kind)
    assert seen == {"exact", "approximate"}
    code, out, err = run(PYTHON, os.path.join(SCRIPTS, "status_table.py"), copy_of)
    assert code == 0, err
    row = next(line for line in out.splitlines() if line.startswith(f"| `{exact[1]['model']}` | exact |"))
    assert "| pass | 0.002 |" in row, row


def test_p_colour_stays_red_at_or_below_a_large_significance(copy_of):
    # At significance 0.45 a p of 0.43 fails: red (hue 0), not green as when green began at 0.05.
    r = results(copy_of)
    r["significance"] = 0.45
    exact = next(c for case in r["cases"] for c in case["checks"] if c["exact"] and c["status"] == "pass")
    for case in r["cases"]:
        for c in case["checks"]:
            if c["model"] == exact["model"]:
                c["p_value"] = 0.43
    with open(os.path.join(copy_of, "results.json"), "w") as f:
        json.dump(r, f)
    summary = render(copy_of).split('id="summary"')[1].split("<details")[0]
    row = re.search(rf"<code>{re.escape(exact['model'])}</code></td><td>exact</td>(.*?)</tr>", summary, re.S).group(1)
    assert re.findall(r'style="background: ([^"]*)">([^<]*)</td>', row)[0] == ("hsl(0, 70%, 82%)", "0.43"), row
    assert "from green (&ge; 0.9)" in summary


def test_case_names_are_quoted_in_links(copy_of):
    # A case named a#1 links to #case-a%231 (a raw '#' or '?' cut the link short).
    r = results(copy_of)
    r["cases"][0]["name"] = "a#1"
    with open(os.path.join(copy_of, "results.json"), "w") as f:
        json.dump(r, f)
    text = render(copy_of)
    assert '<a href="#case-a%231">' in text and 'href="#case-a#1"' not in text


def test_every_plot_of_a_case_is_embedded_and_figure_plots_are_indexed(copy_of):
    plots = os.path.join(copy_of, "plots")
    first = first_png(plots)
    case = results(copy_of)["cases"][0]
    shutil.copy(os.path.join(plots, first), os.path.join(plots, case["name"] + "_lobes.png"))
    figure_plot = f"figure_{figure_slug(case['figure'])}.png"
    shutil.copy(os.path.join(plots, first), os.path.join(plots, figure_plot))
    pngs = [f for f in os.listdir(plots) if f.endswith(".png")]
    plot_manifest.write(copy_of, pngs)  # as plot_validation.py records what it made
    text = render(copy_of)
    for f in pngs:
        if f != figure_plot:
            assert f'<img src="plots/{f}"' in text, f
    index = text.split('id="figures"')[1].split('id="not-reproduced"')[0]
    assert f'<img src="plots/{figure_plot}"' in index
    section = text.split(f'id="case-{case["name"]}"')[1].split("<h3")[0]
    assert f'<img src="plots/{case["name"]}_lobes.png"' in section


def test_only_the_plots_made_from_this_run_are_shown(copy_of):
    # A later `mcref validate --case X` into the same OUTDIR leaves the other
    # cases' plots (and earlier runs' overlays) in plots/: a plot whose name
    # starts with X's was embedded in X's section, and a stale overlay in the index.
    plots = os.path.join(copy_of, "plots")
    case = results(copy_of)["cases"][0]
    shutil.copy(os.path.join(plots, first_png(plots)), os.path.join(plots, case["name"] + "_other_case.png"))
    text = render(copy_of)
    assert f'plots/{case["name"]}_other_case.png' not in text
    own = [f for f in plot_manifest.read(copy_of)[0] if f.startswith(case["name"])]
    assert own and all(f'<img src="plots/{f}"' in text for f in own)
    # results.json changed since the plots were made (a new run): none is shown, and the report says why.
    with open(os.path.join(copy_of, "results.json"), "a") as f:
        f.write("\n")
    code, _, err = run(PYTHON, os.path.join(SCRIPTS, "report.py"), copy_of)
    assert code == 0, err
    assert "no plots shown: the plots in" in err and "made from another results.json" in err
    assert '<img src="plots/' not in page(copy_of)


@pytest.mark.parametrize("content, message", [
    (None, "results.json: No such file or directory"),
    ('{"title": "x", ', "results.json: not valid JSON"),
    ("[1, 2]", "not a JSON object"),
    ("42", "not a JSON object"),
    ('{"title": "x", "significance": 0.001, "cases": [{"name": "c"}]}', "not a results.json of this mcref"),
])
def test_report_refuses_what_is_not_a_run_in_one_line(tmp_path, content, message):
    if content is not None:
        (tmp_path / "results.json").write_text(content)
    code, _, err = run(PYTHON, os.path.join(SCRIPTS, "report.py"), str(tmp_path))
    assert code != 0 and "Traceback" not in err, err
    assert len(err.strip().splitlines()) == 1 and message in err, err
    assert not (tmp_path / "report.html").exists()


@pytest.mark.parametrize("content, args, message", [
    (None, [], "results.json: No such file or directory"),
    ('{"title": "x", ', [], "results.json: not valid JSON"),
    ("[1, 2]", [], 'no list "cases"'),
    ('{"cases": [{"name": "c", "tables": "tables/c.h5", "checks": []}]}', [], "tables/c.h5: missing"),
    ('{"cases": []}', ["--jobs"], "--jobs needs a whole number"),
    ('{"cases": []}', ["--jobs", "0"], "--jobs needs a whole number"),
])
def test_plot_validation_refuses_what_is_not_a_run_in_one_line(tmp_path, content, args, message):
    if content is not None:
        (tmp_path / "results.json").write_text(content)
    code, _, err = run(PYTHON, os.path.join(SCRIPTS, "plot_validation.py"), str(tmp_path), *args)
    assert code != 0 and "Traceback" not in err, err
    assert len(err.strip().splitlines()) == 1 and message in err, err
    assert not (tmp_path / "plots").exists()


def test_figure_index_lists_cases_and_the_figures_not_reproduced(run_dir, copy_of):
    text = page(run_dir)
    index = text.split('id="figures"')[1]
    for case in results(run_dir)["cases"]:
        assert f"<h3>{html.escape(case['figure'])}</h3>" in index
        assert f'<a href="#case-{case["name"]}">' in index
    with open(os.path.join(SOURCE_DIR, "validate/figures_not_reproduced.toml"), "rb") as f:
        listed = tomllib.load(f)
    missing = listed["figure"]
    # The list describes its own suite's figures: another suite's report leaves it out.
    assert results(run_dir)["suite"] != listed["suite"]
    assert 'id="not-reproduced"' not in text
    r = results(copy_of)
    r["suite"] = listed["suite"]
    with open(os.path.join(copy_of, "results.json"), "w") as f:
        json.dump(r, f)
    index = render(copy_of).split('id="figures"')[1]
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
    broken = first_png(plots)
    with open(os.path.join(plots, broken), "wb") as f:
        f.write(b"not a png")
    text = page(copy_of).replace("</body>", "<script>undefined_function();</script></body>")
    problems = browser_problems(copy_of, tmp_path, text)
    assert f"image not shown: plots/{broken}" in problems
    assert any(p.startswith("error:") and "undefined_function" in p for p in problems)


# SpongeCake's section (scripts/spongecake/stage.py writes OUTDIR/spongecake/summary.json):
# a fixture of two sets, one with a NaN-free row and one whose ms table is empty (nulls).
def spongecake_fixture(out, png_source):
    row = {"entry": 9, "type": "fiber", "alpha": 0.3, "albedo": 0.5, "thickness": 2.0, "mean_abs_ms": 0.01,
           "network_ms": 0.791, "fit_ms": 0.623, "lambert_ms": 0.995, "none_ms": 1.0, "noise_ms": 0.17,
           "sscheck_ms": 0.12, "network_total": 0.107, "fit_total": 0.071, "lambert_total": 0.15, "none_total": 0.156,
           "sscheck_total": 0.12, "stack": "fiber a=0.30 T=2.00 g=0.50", "label": ""}
    empty = dict(row, entry=3, mean_abs_ms=0.0, network_ms=None, fit_ms=None, lambert_ms=None, noise_ms=None,
                 label="Fig. 7's stack", stack="surface a=0.50 T=0.50 g=0.90 / surface a=0.90 T=2.00 g=0.90")
    dist = lambda v: {"ms": [v, v, v], "total": [v / 10, v / 10, v / 10]}  # noqa: E731
    distribution = {m: dist(v) for m, v in (("network", 0.791), ("fit", 0.623), ("lambert", 0.995), ("none", 1.0))}
    distribution.update(noise={"ms": [0.17, 0.17, 0.17]}, sscheck={"ms": [None, None, None]})
    scale = {"entries": 300, "incident_directions": [8, 8], "outgoing_bins": [8, 8], "paths_per_direction": 40000,
             "max_order": 20, "fitted_entries": 30, "fit_starts": 3, "fit_iterations": 10, "network_dataset": "sc1.h5",
             "epochs": 617, "cells_per_batch": 1024, "batch": 32, "lr": 0.001, "train_entries": 270, "seed": 1}
    sets = [{"name": "one_layer", "kind": "network", "network": "one_layer", "layers": 1, "figure": "",
             "dataset": "validate/datasets/spongecake_1layer_reduced.toml", "scale": scale, "rows": [row],
             "distribution": distribution, "figures": ["one_layer_bsdf.png"]},
            {"name": "paper_two_layers", "kind": "materials", "network": "two_layers", "layers": 2,
             "figure": "SpongeCake Figs. 11-13", "dataset": "validate/datasets/spongecake_paper_2layer.toml",
             "scale": dict(scale, entries=7), "rows": [empty], "distribution": distribution,
             "figures": ["paper_two_layers_bsdf.png"]}]
    os.makedirs(os.path.join(out, "spongecake"))
    for s in sets:
        shutil.copy(png_source, os.path.join(out, "spongecake", s["figures"][0]))
    summary = {"format": "mcref-spongecake-summary", "format_version": 1, "stage": "stage.toml", "seed": 1,
               "wall_s": 612.0, "cpu_s": 1100.0, "steps": {}, "sets": sets}
    with open(os.path.join(out, "spongecake", "summary.json"), "w") as f:
        json.dump(summary, f)
    return summary


def test_spongecake_section_renders_the_summary(copy_of, tmp_path):
    assert 'id="spongecake"' not in page(copy_of)  # no summary, no section
    plots = os.path.join(copy_of, "plots")
    spongecake_fixture(copy_of, os.path.join(plots, first_png(plots)))
    text = render(copy_of)
    section = text.split('id="spongecake"')[1].split('id="figures"')[0]
    flat = re.sub(r"\s+", " ", html.unescape(re.sub(r"<[^>]+>", " ", section)))
    # the scale it ran at
    assert "300 entries, 8 × 8 incident directions" in flat and "40000 paths per direction" in flat
    assert "617 epochs" in flat and "270 training entries" in flat and "1024 cells per batch" in flat
    # one row per entry, one number per method; nulls shown as a dash
    one = section.split('id="spongecake-one_layer"')[1].split('id="spongecake-paper_two_layers"')[0]
    rows = re.findall(r"<tr><td class=\"num\">(\d+)</td>(.*?)</tr>", one, re.S)
    assert [r[0] for r in rows] == ["9"]
    cells = re.findall(r'<td class="num">([^<]*)</td>', rows[0][1])
    assert cells == ["79.1 %", "62.3 %", "99.5 %", "100.0 %", "17.0 %", "12.0 %", "10.7 %", "15.6 %"]
    two = section.split('id="spongecake-paper_two_layers"')[1]
    assert "Fig. 7's stack" in html.unescape(two) and "never saw" in two and "Figs. 11-13" in two
    assert re.findall(r'<td class="num">([^<]*)</td>', two.split("Fig. 7")[1].split("</tr>")[0])[:2] == ["–", "–"]
    # the distribution table and the figures
    assert "<td>network</td><td class=\"num\">79.1 %</td>" in one and "<td>noise level</td>" in one
    for name in ("one_layer_bsdf.png", "paper_two_layers_bsdf.png"):
        assert f'<img src="spongecake/{name}"' in section
    assert browser_problems(copy_of, tmp_path) == []  # the images load from spongecake/


def test_spongecake_summary_of_another_format_is_refused(copy_of):
    os.makedirs(os.path.join(copy_of, "spongecake"))
    with open(os.path.join(copy_of, "spongecake", "summary.json"), "w") as f:
        json.dump({"format": "something-else", "sets": []}, f)
    before = page(copy_of)
    code, _, err = run(PYTHON, os.path.join(SCRIPTS, "report.py"), copy_of, "--quiet")
    assert code != 0 and "summary.json" in err and "something-else" in err and len(err.strip().splitlines()) == 1
    assert page(copy_of) == before  # the old page is kept


def test_status_table_has_the_spongecake_block(copy_of):
    code, out, err = run(PYTHON, os.path.join(SCRIPTS, "status_table.py"), copy_of)
    assert code == 0 and "SpongeCake" not in out, err
    plots = os.path.join(copy_of, "plots")
    spongecake_fixture(copy_of, os.path.join(plots, first_png(plots)))
    code, out, err = run(PYTHON, os.path.join(SCRIPTS, "status_table.py"), copy_of)
    assert code == 0, err
    rows = [l for l in out.splitlines() if l.startswith("| `one_layer`") or l.startswith("| `paper_two_layers`")]
    assert len(rows) == 2
    assert "| 1 | 300 entries, 8×8 dir., 8×8 bins, 4e+04 paths, 617 epochs | 1 held out | 79 % (79 %) | 62 % (62 %) |" \
        in rows[0]
    # network, fit, Lambertian, noise (of ms), then network and no term of the BSDF; median (90th percentile)
    assert rows[0].endswith("| 17 % (17 %) | 8 % (8 %) | 10 % (10 %) |"), rows[0]
    assert "unseen (SpongeCake Figs. 11-13)" in rows[1]


def test_model_rule_accuracy_is_reported_and_a_short_rule_flagged(copy_of):
    """Checks whose model is an adaptive integral (rule_accuracy in results.json,
    written by mcref validate for the micrograin BRDF models) show the rule's
    largest error estimate; integrals that stopped above the target are named
    in the page's opening and flagged. The tiny suite's one such check
    converged; a second record, short of its target, is added here."""
    r = results(copy_of)
    checks = [c for case in r["cases"] for c in case["checks"]]
    ruled = [c for c in checks if "rule_accuracy" in c]
    assert len(ruled) == 1 and ruled[0]["rule_accuracy"]["unconverged"] == 0
    real = ruled[0]["rule_accuracy"]
    p = page(copy_of)
    worst = format(real["worst_rel_error"], ".3g")
    assert "Model integrals: in 1 check, the model" in p and f"largest error estimate reached is {worst}." in p
    assert "Every integral reached the target." in p and f'<td class="num">{worst}</td>' in p
    assert "short" not in p.split("<body>")[1]

    case, other = next((k["name"], c) for k in r["cases"] for c in k["checks"] if "rule_accuracy" not in c)
    other["rule_accuracy"] = {"target": 5e-7, "integrals": 10, "unconverged": 2, "worst_rel_error": 7.9e-7, "worst_cell": 4}
    with open(os.path.join(copy_of, "results.json"), "w") as f:
        json.dump(r, f)
    p = render(copy_of)
    assert "Model integrals: in 2 checks" in p and "largest error estimate reached is 7.9e-07." in p
    assert '<span class="short">In 1 of them some integrals stopped above the target</span>' in p
    assert f"{case}: {other['model']} on <code>{html.escape(other['table'])}</code>, 2\nof 10, up to 7.9e-07" in p
    assert '<td class="num short">7.9e-07</td>' in p and f'<td class="num">{worst}</td>' in p
    assert "2 stopped above the target, the worst at model value 4" in p


def test_results_hold_each_cells_z_and_the_plots_read_it(run_dir):
    # The plots' residual panels show the report's z (they drew (model - sim)/sigma,
    # without the Student-t mapping: another sign, and larger with few batches).
    import validation_data
    compared = 0
    for case in results(run_dir)["cases"]:
        loaded = validation_data.load_case(run_dir, case)
        for chk in case["checks"]:
            assert len(chk["z"]) == len(chk["model_values"]), chk["model"]
            z = [abs(v) for v in chk["z"] if v is not None]
            if chk["max_abs_z"] is None or not z:
                continue
            assert abs(max(z) - chk["max_abs_z"]) <= 1e-8 * max(1.0, chk["max_abs_z"]), chk["model"]
            model = next(m for t in loaded.tables for m in t.models if m.name == chk["model"] and t.name == chk["table"])
            assert model.z is not None and model.z.shape == model.values.shape
            compared += 1
    assert compared >= 1


def test_plots_refuse_tables_that_results_json_did_not_judge(copy_of):
    # A validate run stopped after rewriting a case's tables (a full disk, Ctrl-C) leaves the old
    # results.json beside them: its z values and verdicts are not those tables'.
    import h5py
    case = results(copy_of)["cases"][0]
    with h5py.File(os.path.join(copy_of, case["tables"]), "r+") as h5:
        h5.attrs["created"] = "2000-01-01T00:00:00Z"
    code, _, err = run(PYTHON, os.path.join(SCRIPTS, "plot_validation.py"), copy_of, "--quiet")
    assert code != 0 and "Traceback" not in err, err
    assert len(err.strip().splitlines()) == 1, err
    assert case["tables"] in err and "not the tables" in err and "2000-01-01" in err, err
