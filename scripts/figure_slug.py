"""The file-name slug of a paper figure label (a case's `figure` in a suite).

Figure-level plots are OUTDIR/plots/figure_<slug>.png: scripts/report.py
embeds them in its figure index under that figure, scripts/plot_validation.py
writes them. Both import this one rule: lower-cased, every run of characters
other than a-z and 0-9 replaced by one "_", none at either end.
"LRPB23 Fig. 5" -> "lrpb23_fig_5".
"""
import re


def figure_slug(figure):
    return re.sub(r"[^a-z0-9]+", "_", figure.lower()).strip("_")
