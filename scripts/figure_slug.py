import re


def figure_slug(figure):
    """The file-name slug of a paper figure label: lower case, runs of non-alphanumerics as '_'."""
    return re.sub(r"[^a-z0-9]+", "_", figure.lower()).strip("_")
