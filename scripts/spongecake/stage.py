#!/usr/bin/python3
"""The SpongeCake stage of scripts/run.sh: SpongeCake's multiple-scattering
approximation (Wang et al. 2022, Sec. 5) end to end at the scale a stage file
gives (validate/spongecake_stage.toml), into OUTDIR:

  1. the datasets (`mcref dataset ... --lean`), one per [[network]] and [[materials]];
  2. per-material fits (fit_dataset.py): a network's held-out entries (index % 10 == 9)
     or all its entries (fit = "all"), and every entry of a materials set;
  3. one network per [[network]] (train.py, its report beside the fits' errors);
  4. figures and per-entry errors (figures.py --summary): a network's held-out entries,
     and a materials set's entries, unseen by the network it names;
  5. OUTDIR/summary.json: the scale each set ran at, one row per entry with one number
     per method, the distributions, the figures and the time each step took
     (scripts/report.py renders it, scripts/status_table.py sums it up).

A step is skipped when its output is up to date: `mcref dataset` itself keeps a file
that holds the same dataset from the same simulation fingerprint (a stale one is
removed and simulated again); a Python step is skipped when OUTDIR/stage.json records
it with the same key (the SHA-256 of its command line, of its input files and of the
scripts/spongecake/*.py sources but this one) and its outputs are unchanged; each step is
recorded there as soon as it finishes, so an interrupted stage runs again only the steps
it had not finished. Steps 2-4 run as separate processes, --jobs at once (one torch
thread each, so the results do not depend on it). summary.json is removed first and
written last, so a failed stage leaves none. Progress lines go to stderr unless --quiet;
one summary line at the end.

Before anything runs, the stage file is checked whole, and each dataset file as `mcref
dataset` checks it (nothing simulated): a [[network]] dataset needs at least 10 entries
(held-out and training ones), a [[materials]] dataset must not be its network's, and
`labels` gives one label per entry.

  /usr/bin/python3 scripts/spongecake/stage.py STAGE.toml OUTDIR --mcref BINARY
      [--threads N] [--jobs N] [--quiet]
Exit: 0 done; 1 a step failed (its message is printed); 2 bad input (nothing run).
"""
import argparse
import concurrent.futures
import hashlib
import json
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import threading
import time
import tomllib

import h5py

HERE = os.path.dirname(os.path.abspath(__file__))
if __package__ in (None, ""):
    sys.path.insert(0, os.path.dirname(HERE))
from spongecake import dataset, errors, files, fit, fit_dataset, network  # noqa: E402
from spongecake.train import is_validation  # noqa: E402

FORMAT = "mcref-spongecake-summary"
PYTHON = sys.executable
NETWORK_KEYS = {"name": str, "dataset": str, "fit": str, "starts": int, "iterations": int, "epochs": int,
                "cells": int}
MATERIALS_KEYS = {"name": str, "dataset": str, "network": str, "starts": int, "iterations": int, "labels": list,
                  "figure": str}
INT_MAX = 2 ** 63 - 1  # the steps store these settings as HDF5 attributes (int64)
MIN_NETWORK_ENTRIES = 10  # entries 0-9: one held out (index % 10 == 9), nine to train on


class StageError(Exception):
    pass


def read_stage(path):
    """The stage file, checked: one-line errors name the file, the key, the value and what is allowed."""
    try:
        with open(path, "rb") as f:
            cfg = tomllib.load(f)
    except (OSError, tomllib.TOMLDecodeError) as e:
        raise StageError(f"{path}: {e}")
    unknown = set(cfg) - {"seed", "network", "materials"}
    if unknown:
        raise StageError(f"{path}: {sorted(unknown)[0]}: not a stage key (allowed: seed, network, materials)")
    seed = cfg.get("seed", 1)
    if not isinstance(seed, int) or isinstance(seed, bool) or not fit.SEED_RANGE[0] <= seed <= fit.SEED_RANGE[1]:
        raise StageError(f"{path}: seed = {seed!r} (allowed: an integer in [0, 2^64 - 1], what torch takes)")
    for kind in ("network", "materials"):
        v = cfg.get(kind, [])
        if not isinstance(v, list) or not all(isinstance(t, dict) for t in v):
            raise StageError(f"{path}: {kind} = {v!r} (allowed: tables [[{kind}]])")
    names = set()

    def check(kind, i, t, keys, required):
        where = f"{path}: {kind}.{i}"
        for k, v in t.items():
            if k not in keys:
                raise StageError(f"{where}.{k}: not a {kind} key (allowed: {', '.join(keys)})")
            if not isinstance(v, keys[k]) or isinstance(v, bool):
                raise StageError(f"{where}.{k} = {v!r}: expected {keys[k].__name__}")
            if keys[k] is int and v < 1:
                raise StageError(f"{where}.{k} = {v}: allowed >= 1")
            if keys[k] is int and v > INT_MAX:
                raise StageError(f"{where}.{k} = {v}: allowed <= 2^63 - 1")
            if k == "labels" and not all(isinstance(x, str) for x in v):
                raise StageError(f"{where}.labels = {v!r}: expected strings")
        for k in required:
            if k not in t:
                raise StageError(f"{where}.{k}: required")
        if t["name"] in names or not t["name"].replace("_", "").isalnum():
            raise StageError(f"{where}.name = {t['name']!r}: must be unique, letters, digits and _")
        names.add(t["name"])
        t["dataset"] = os.path.join(os.path.dirname(os.path.abspath(path)), t["dataset"])
        if not os.path.isfile(t["dataset"]):
            raise StageError(f"{where}.dataset = {t['dataset']!r}: no such file")
        t.setdefault("starts", 3)
        t.setdefault("iterations", 10)

    nets = cfg.get("network", [])
    for i, t in enumerate(nets):
        check("network", i, t, NETWORK_KEYS, ("name", "dataset", "epochs"))
        t.setdefault("fit", "held_out")
        if t["fit"] not in ("held_out", "all"):
            raise StageError(f"{path}: network.{i}.fit = {t['fit']!r} (allowed: 'held_out', 'all')")
    mats = cfg.get("materials", [])
    for i, t in enumerate(mats):
        check("materials", i, t, MATERIALS_KEYS, ("name", "dataset", "network"))
        if t["network"] not in [n["name"] for n in nets]:
            raise StageError(f"{path}: materials.{i}.network = {t['network']!r} (allowed: the names of [[network]]: "
                             f"{[n['name'] for n in nets]})")
    if not nets:
        raise StageError(f"{path}: network: at least one [[network]] is required")
    return seed, nets, mats


def read_dataset_file(path):
    """(entries, identity) of a dataset file, read after `mcref dataset` has checked it. Entries
    (README, "Reference datasets"): `entries` (1) per point of the grid of the parameters given
    by `values`. Identity: the SHA-256 of the file and of its base experiment (two files with
    both the same make the same dataset)."""
    with open(path, "rb") as f:
        cfg = tomllib.load(f)
    n = cfg["dataset"].get("entries", 1)
    for p in cfg.get("parameter", []):
        if "values" in p:
            n *= len(p["values"])
    experiment = os.path.join(os.path.dirname(os.path.abspath(path)), cfg["dataset"]["experiment"])
    return n, (sha256_file(path), sha256_file(experiment))


def check_datasets(path, mcref, nets, mats):
    """Before anything is simulated: each dataset file as `mcref dataset` checks it (--stop-after
    0 into a temporary directory: every parameter value, nothing simulated), a network's dataset
    with held-out and training entries, a materials set's dataset not its network's, one label per
    entry. One-line errors name the stage file, the key and the value."""
    identity = {}
    with tempfile.TemporaryDirectory() as tmp:
        for kind, sets in (("network", nets), ("materials", mats)):
            for i, t in enumerate(sets):
                where = f"{path}: {kind}.{i}.dataset = {t['dataset']!r}"
                p = subprocess.run([mcref, "dataset", t["dataset"], "-o", os.path.join(tmp, f"{kind}{i}.h5"),
                                    "--stop-after", "0", "--quiet", "--threads", "1"], capture_output=True, text=True)
                if p.returncode != 0:
                    raise StageError(f"{where}: {(p.stderr.strip().splitlines() or [f'exit {p.returncode}'])[-1]}")
                try:
                    t["entries"], identity[t["name"]] = read_dataset_file(t["dataset"])
                except (OSError, tomllib.TOMLDecodeError, KeyError, TypeError, AttributeError) as e:
                    raise StageError(f"{where}: cannot read its entry count ({e})")
    for i, t in enumerate(nets):
        if t["entries"] < MIN_NETWORK_ENTRIES:
            raise StageError(f"{path}: network.{i}.dataset = {t['dataset']!r}: {t['entries']} entries (allowed: at "
                             f"least {MIN_NETWORK_ENTRIES}: entries with index % 10 == 9 are held out and judged, the "
                             "others train)")
    by_name = {t["name"]: t for t in nets}
    for i, t in enumerate(mats):
        own = by_name[t["network"]]["dataset"]
        if files.same_file(t["dataset"], own) or identity[t["name"]] == identity[t["network"]]:
            raise StageError(f"{path}: materials.{i}.dataset = {t['dataset']!r}: the dataset of its network "
                             f"{t['network']!r} (allowed: a dataset the network never saw)")
        if "labels" in t and len(t["labels"]) != t["entries"]:
            raise StageError(f"{path}: materials.{i}.labels: {len(t['labels'])} labels (allowed: one per entry of "
                             f"{t['dataset']}, {t['entries']})")


def sha256_file(path):
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def code_hash():
    """The scripts a step runs and what they import: scripts/spongecake/*.py but this one
    (its command lines are in the keys)."""
    h = hashlib.sha256()
    for name in sorted(os.listdir(HERE)):
        if name.endswith(".py") and name != "stage.py":
            h.update(name.encode())
            with open(os.path.join(HERE, name), "rb") as f:
                h.update(f.read())
    return h.hexdigest()


class Stage:
    def __init__(self, out, mcref, threads, jobs, quiet):
        self.out, self.mcref, self.threads, self.jobs, self.quiet = out, mcref, threads, jobs, quiet
        self.manifest_path = os.path.join(out, "stage.json")
        try:
            with open(self.manifest_path) as f:
                self.manifest = json.load(f)
        except (OSError, ValueError):
            self.manifest = {}
        self.code = code_hash()
        self.times = {}
        self.lock = threading.Lock()  # the manifest, written by the steps' threads

    def log(self, text):
        if not self.quiet:
            print(f"spongecake: {text}", file=sys.stderr, flush=True)

    def path(self, name):
        return os.path.join(self.out, name)

    def run(self, label, cmd):
        """Runs cmd; returns its stdout; raises StageError with its last stderr line on failure.
        Records its wall and CPU seconds (its own rusage, os.wait4) under label."""
        start = time.monotonic()
        with tempfile.TemporaryFile("w+") as out, tempfile.TemporaryFile("w+") as err:
            p = subprocess.Popen(cmd, stdout=out, stderr=err, text=True)
            _, status, used = os.wait4(p.pid, 0)
            p.returncode = os.waitstatus_to_exitcode(status)
            out.seek(0)
            err.seek(0)
            stdout, stderr = out.read(), err.read()
        self.times[label] = {"wall_s": round(time.monotonic() - start, 1), "cpu_s": round(used.ru_utime + used.ru_stime, 1)}
        if p.returncode != 0:
            last = (stderr.strip().splitlines() or [f"exit {p.returncode}"])[-1]
            raise StageError(f"{label}: {last}")
        return stdout

    def dataset(self, name, toml):
        """Step 1: the dataset file (mcref's own up-to-date check; a stale file is simulated again)."""
        out = self.path(f"{name}.h5")
        cmd = [self.mcref, "dataset", toml, "-o", out, "--lean", "--quiet", "--threads", str(self.threads)]
        self.log(f"{name}: dataset {os.path.basename(toml)}")
        before = os.stat(out).st_mtime_ns if os.path.exists(out) else None
        try:
            self.run(f"{name} dataset", cmd)
            if before is not None and os.stat(out).st_mtime_ns == before:  # mcref found it up to date
                self.times[f"{name} dataset"]["cached"] = True
        except StageError as e:
            # Only mcref's own two verdicts on this stage's files: OUTPUT of another dataset
            # (or incomplete, unreadable), or parts of another dataset (its TOML changed after
            # an interrupted run). Anything else (a file where the parts directory goes) is raised.
            stale_output = f"{out}: exists and " in str(e)
            stale_parts = f"{out}.parts: holds entries of another dataset" in str(e)
            if not (stale_output or stale_parts):
                raise
            self.log(f"{name}: {out if stale_output else out + '.parts'} is stale ({str(e).split(': ', 1)[1]}); "
                     "simulating again")
            if stale_output:
                os.remove(out)
            shutil.rmtree(out + ".parts", ignore_errors=True)
            self.run(f"{name} dataset", cmd)
        return out

    def cached(self, label, cmd, inputs, outputs):
        """Steps 2-4: runs cmd unless stage.json records it with the same key and its outputs
        are unchanged; returns (stdout or the recorded one, whether it ran)."""
        rel = [os.path.relpath(c, self.out) if os.path.isabs(c) and c.startswith(self.out) else c for c in cmd[1:]]
        key = hashlib.sha256(json.dumps({"cmd": rel, "inputs": [sha256_file(p) for p in inputs],
                                         "code": self.code}).encode()).hexdigest()
        done = self.manifest.get(label)
        if done and done["key"] == key and all(os.path.exists(p) and sha256_file(p) == done["outputs"].get(
                os.path.basename(p)) for p in outputs):
            self.log(f"{label}: up to date")
            self.times[label] = dict(done["times"], cached=True)
            return done["stdout"], False
        self.log(f"{label}: running")
        stdout = self.run(label, cmd)
        with self.lock:  # recorded at once: a stage interrupted later does not run this step again
            self.manifest[label] = {"key": key, "outputs": {os.path.basename(p): sha256_file(p) for p in outputs},
                                    "times": self.times[label], "stdout": stdout}
            self.write_manifest()
        self.log(f"{label}: done in {self.times[label]['wall_s']:.0f} s")
        return stdout, True

    def save_manifest(self):
        with self.lock:
            self.write_manifest()

    def write_manifest(self):
        """stage.json, whole (a temporary file renamed into place); the caller holds self.lock."""
        tmp = f"{self.manifest_path}.tmp.{os.getpid()}"
        with open(tmp, "w") as f:
            json.dump(self.manifest, f, indent=1)
        os.replace(tmp, self.manifest_path)


def script(name):
    return os.path.join(HERE, name)


def scale(data_path, fits_path, weights_path):
    """What a set ran at: from the dataset file, the fits and the weights."""
    indices = dataset.entry_indices(data_path)
    with h5py.File(data_path, "r") as f:
        g = f[f"entries/{indices[0]}/brdf"]
        config = g.file[f"entries/{indices[0]}"].attrs["config"]
        config = tomllib.loads(config.decode() if isinstance(config, bytes) else config)
        measure = config["measure"][0]
        out = {"entries": len(indices), "incident_directions": [len(g["theta_i"]), len(g["phi_i"])],
               "outgoing_bins": [len(g["theta_o"]), len(g["phi"])],
               "paths_per_direction": int(measure["samples"]) * int(config["run"].get("batches", 1)),
               "max_order": int(measure.get("max_order", 0)), "dataset_config": f.attrs["experiment_file"]
               if isinstance(f.attrs["experiment_file"], str) else f.attrs["experiment_file"].decode()}
    _, fattrs = fit_dataset.read(fits_path)
    d, _ = fit_dataset.read(fits_path)
    out.update(fitted_entries=len(d["index"]), fit_starts=int(fattrs["starts"]), fit_iterations=int(fattrs["iterations"]))
    _, nattrs = network.load(weights_path)
    out.update(network_dataset=os.path.basename(str(nattrs["dataset"])), epochs=int(nattrs["epochs"]),
               cells_per_batch=int(nattrs["cells"]), batch=int(nattrs["batch"]), lr=float(nattrs["lr"]),
               train_entries=int(nattrs["train_entries"]), seed=int(nattrs["seed"]))
    return out


def check_outputs(out, sets, inputs):
    """Before any step: none of the files the stage writes into OUT is one of its inputs."""
    names = ["summary.json", "stage.json"] + [f"{t['name']}{k}" for t in sets for k in (
        ".h5", "_fits.h5", "_net.h5", "_summary.json", "_bsdf.png", "_lobes.png", "_errors.png")]
    for name in names:
        for key, path in inputs:
            if files.same_file(os.path.join(out, name), path):
                raise StageError(f"{os.path.join(out, name)}: an output of the stage is the input {key} {path} "
                                 "(allowed: an OUTDIR holding none of the inputs)")


METHODS = ("network", "fit", "lambert", "none", "noise", "sscheck")


def distributions(rows):
    """Per method: [median, 90th percentile, worst] of the error relative to the multiple
    scattering ("ms") and to the whole BSDF ("total"; not for noise and sscheck), over
    the rows with a non-empty multiple-scattering table; null where none."""
    usable = [r for r in rows if r["mean_abs_ms"] > 0]
    clean = lambda v: [None if x != x else x for x in v]  # noqa: E731  NaN -> null
    out = {}
    for m in METHODS:
        out[m] = {"ms": clean(errors.distribution([r[f"{m}_ms"] for r in usable if r.get(f"{m}_ms") is not None]))}
        if m not in ("noise", "sscheck"):
            out[m]["total"] = clean(errors.distribution([r[f"{m}_total"] for r in usable
                                                         if r.get(f"{m}_total") is not None]))
    return out


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("stage", help="stage file (validate/spongecake_stage.toml)")
    p.add_argument("out", help="output directory (created if its parent exists)")
    p.add_argument("--mcref", required=True, help="the mcref binary")
    p.add_argument("--threads", type=int, default=os.cpu_count() or 1, help="threads of mcref dataset")
    p.add_argument("--jobs", type=int, default=min(2, os.cpu_count() or 1), help="Python steps at once")
    p.add_argument("-q", "--quiet", action="store_true")
    a = p.parse_args(argv)
    started = time.monotonic()
    try:
        if a.threads < 1 or a.threads > 1024 or a.jobs < 1 or a.jobs > 64:
            raise StageError(f"--threads = {a.threads}, --jobs = {a.jobs} (allowed: threads in [1, 1024], jobs in [1, 64])")
        if not (os.path.isfile(a.mcref) and os.access(a.mcref, os.X_OK)):
            raise StageError(f"--mcref {a.mcref}: not an executable file")
        seed, nets, mats = read_stage(a.stage)
        out = os.path.abspath(a.out)
        if not os.path.isdir(os.path.dirname(out)):
            raise StageError(f"{a.out}: its directory {os.path.dirname(out)} does not exist")
        if os.path.lexists(out) and not os.path.isdir(out):
            raise StageError(f"{a.out}: exists and is not a directory (allowed: a directory, or a new name)")
        check_outputs(out, nets + mats, [("STAGE.toml", a.stage), ("--mcref", a.mcref)] +
                      [(f"{t['name']}.dataset", t["dataset"]) for t in nets + mats])
        check_datasets(a.stage, a.mcref, nets, mats)
        os.makedirs(out, exist_ok=True)
    except StageError as e:
        print(f"stage: {e}", file=sys.stderr)
        return 2
    summary_path = os.path.join(out, "summary.json")
    if os.path.exists(summary_path):
        os.remove(summary_path)
    stage = Stage(out, a.mcref, a.threads, a.jobs, a.quiet)
    cpu0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    try:
        data = {t["name"]: stage.dataset(t["name"], t["dataset"]) for t in nets + mats}
        sets = {t["name"]: t for t in nets + mats}

        def fits(t):
            entries = dataset.entry_indices(data[t["name"]])
            if t in nets and t["fit"] == "held_out":
                entries = [i for i in entries if is_validation(i)]
            out_path = stage.path(f"{t['name']}_fits.h5")
            cmd = [PYTHON, script("fit_dataset.py"), data[t["name"]], "-o", out_path, "--entries",
                   ",".join(map(str, entries)), "--starts", str(t["starts"]), "--iterations", str(t["iterations"]),
                   "--seed", str(seed), "--quiet"]
            stage.cached(f"{t['name']} fits", cmd, [data[t["name"]]], [out_path])

        def train(t):
            out_path, fits_path = stage.path(f"{t['name']}_net.h5"), stage.path(f"{t['name']}_fits.h5")
            cmd = [PYTHON, script("train.py"), data[t["name"]], "-o", out_path, "--epochs", str(t["epochs"]),
                   "--seed", str(seed), "--fits", fits_path, "--quiet"] + (
                ["--cells", str(t["cells"])] if "cells" in t else [])
            stage.cached(f"{t['name']} network", cmd, [data[t["name"]], fits_path], [out_path])

        def figures(t):
            net = sets[t.get("network", t["name"])]["name"]
            paths = [data[t["name"]], stage.path(f"{t['name']}_fits.h5"), stage.path(f"{net}_net.h5")]
            summary = stage.path(f"{t['name']}_summary.json")
            cmd = [PYTHON, script("figures.py"), *paths, "-o", out, "--prefix", t["name"], "--summary", summary] + (
                ["--unseen", "--show", "all"] if t in mats else [])
            pngs = [stage.path(f"{t['name']}_{k}.png") for k in ("bsdf", "lobes", "errors")]
            stage.cached(f"{t['name']} figures", cmd, paths, [summary] + pngs)

        with concurrent.futures.ThreadPoolExecutor(a.jobs) as pool:
            for step, group in ((fits, nets + mats), (train, nets), (figures, nets + mats)):
                list(pool.map(step, group))  # each phase waits for the one before; errors propagate
                stage.save_manifest()
        report = []
        for t in nets + mats:
            with open(stage.path(f"{t['name']}_summary.json")) as f:
                s = json.load(f)
            net = sets[t.get("network", t["name"])]["name"]
            s.update(name=t["name"], kind="materials" if t in mats else "network", network=net,
                     dataset=os.path.relpath(t["dataset"], os.getcwd()), figure=t.get("figure", ""),
                     scale=scale(data[t["name"]], stage.path(f"{t['name']}_fits.h5"), stage.path(f"{net}_net.h5")))
            labels = t.get("labels", [])
            for r in s["rows"]:
                r["label"] = labels[r["entry"]] if r["entry"] < len(labels) else ""
            s["layers"] = len(s["rows"][0]["stack"].split(" / ")) if s["rows"] else 0
            s["distribution"] = distributions(s["rows"])
            report.append(s)
    except (StageError, OSError, KeyError, ValueError) as e:
        stage.save_manifest()
        print(f"stage: {e}", file=sys.stderr)
        return 1
    cpu1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    wall = time.monotonic() - started
    cpu = cpu1.ru_utime + cpu1.ru_stime - cpu0.ru_utime - cpu0.ru_stime
    summary = {"format": FORMAT, "format_version": 1, "stage": os.path.relpath(os.path.abspath(a.stage), os.getcwd()),
               "seed": seed, "wall_s": round(wall, 1), "cpu_s": round(cpu, 1), "steps": stage.times, "sets": report}
    tmp = f"{summary_path}.tmp.{os.getpid()}"
    with open(tmp, "w") as f:
        json.dump(summary, f, indent=1)
    os.replace(tmp, summary_path)
    ran = sum(1 for v in stage.times.values() if not v.get("cached"))
    print(f"spongecake stage: {len(report)} sets ({', '.join(s['name'] for s in report)}), {ran} steps run, "
          f"{len(stage.times) - ran} up to date; {wall:.0f} s wall, {cpu:.0f} s CPU -> {summary_path}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
