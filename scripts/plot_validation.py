#!/usr/bin/python3
"""Plots of a validation run, under OUTDIR/plots/:

  <case>.png           the 1-D comparisons: simulation (points, 1-sigma bars), models
                       (lines), and under each the residuals: for exact models the
                       report's z per cell (results.json), for approximate ones
                       model/sim - 1 over the report's cells (|sim| > 5 sigma); a curve
                       with both kinds of model gets both panels
  <case>_table.png     BRDF/BTDF cases: the whole table as an image (rows: incoming
                       directions, columns: outgoing cells, upper | lower hemisphere)
  <case>_lobes.png     BRDF/BTDF cases: polar lobes at a few theta_i: simulation, model,
                       and the residual on a diverging scale (of the channels' mean: z is
                       (sim - model) / sigma there, not the report's per-channel z)
  figure_<slug>.png    each paper figure shared by several cases: their curves overlaid
  plots.json           the plots above and the results.json they were made from
                       (scripts/plot_manifest.py: report.py shows only these)

Reads OUTDIR/results.json (checks, model values per cell) and the simulated tables
OUTDIR/tables/<case>.h5. Needs Debian's python3-matplotlib, python3-h5py, python3-numpy.

usage: /usr/bin/python3 scripts/plot_validation.py OUTDIR [--quiet] [--jobs N]
"""
import multiprocessing
import os
import sys
import time
import warnings

try:
    import plot_style as ps
    import plot_curves
    import plot_manifest
    import plot_figures
    import plot_maps
    import validation_data
except ImportError as e:  # pragma: no cover
    sys.exit(f"plot_validation.py: missing module ({e}); run scripts/setup.sh and use /usr/bin/python3")

warnings.filterwarnings("ignore", message=".*converting a masked element to nan.*")


def plot_case(args):
    """Every per-case plot of one case; returns the file names written."""
    out, case_json = args
    case = validation_data.load_case(out, case_json)
    plots = os.path.join(out, "plots")
    written = []
    fig = plot_curves.case_figure(case)
    if fig is not None:
        ps.save(fig, os.path.join(plots, case.name + ".png"))
        written.append(case.name + ".png")
    for suffix, draw in (("_table", plot_maps.table_figure), ("_lobes", plot_maps.lobes_figure)):
        fig = draw(case)
        if fig is not None:
            ps.save(fig, os.path.join(plots, case.name + suffix + ".png"))
            written.append(case.name + suffix + ".png")
    return written


def main():
    argv = sys.argv[1:]
    quiet = "--quiet" in argv
    jobs = min(os.cpu_count() or 1, 4)
    if "--jobs" in argv:
        at = argv.index("--jobs")
        value = argv[at + 1] if at + 1 < len(argv) else ""
        if not value.isdigit() or int(value) < 1:
            sys.exit(f"plot_validation.py: --jobs needs a whole number of processes >= 1, not \"{value}\"")
        jobs = int(value)
        del argv[at:at + 2]
    args = [a for a in argv if not a.startswith("--")]
    if len(args) != 1:
        sys.exit(__doc__)
    out = args[0]
    start = time.time()
    try:
        results = validation_data.load_results(out)
    except validation_data.RunError as e:
        sys.exit(f"plot_validation.py: {e}")
    os.makedirs(os.path.join(out, "plots"), exist_ok=True)
    work = [(out, c) for c in results["cases"]]
    if jobs > 1 and len(work) > 1:
        with multiprocessing.Pool(jobs) as pool:
            written = [f for fs in pool.map(plot_case, work, chunksize=1) for f in fs]
    else:
        written = [f for w in work for f in plot_case(w)]
    written += plot_figures.write_figures(out, results)
    plot_manifest.write(out, written)
    if not quiet:
        print(f"plot_validation.py: {len(written)} plots in {os.path.join(out, 'plots')} "
              f"({time.time() - start:.1f} s)", file=sys.stderr)


if __name__ == "__main__":
    main()
