"""The README's figure index is the one scripts/figure_index.py generates from the
suites and validate/figures_not_reproduced.toml (so a new case or relabel shows)."""
import os
import subprocess

SCRIPT = os.path.join(os.path.dirname(__file__), "..", "..", "scripts", "figure_index.py")


def test_readme_figure_index_is_current():
    r = subprocess.run(["/usr/bin/python3", SCRIPT, "--check"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr


def test_index_lists_every_suite_figure_and_the_missing_ones():
    text = subprocess.run(["/usr/bin/python3", SCRIPT], capture_output=True, text=True, check=True).stdout
    assert "| LRPB23 Fig. 9 |" in text and "`figure_lrpb23_fig_9.png` (overlay)" in text
    assert "| vNDF paper Fig. 5 | `phi_conditional_triangle_cut` |" in text
    assert "- **vNDF paper Fig. 6.**" in text
