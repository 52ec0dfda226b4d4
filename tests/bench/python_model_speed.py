#!/usr/bin/python3
"""Speed of the Python module's vectorised models against the C++ loop.

Evaluates mcref.micrograin.<model>(0.5, 0.8, theta) over 10^6 points and the
same loop in C++ (bench_model_loop), alternating the two REPS times so that
load from other processes hits both alike; prints the ratio Python / C++ per
model as median and range over the repetitions.

usage: PYTHONPATH=build/python /usr/bin/python3 tests/bench/python_model_speed.py build/bench_model_loop [REPS]
"""
import json
import subprocess
import sys
import time

import numpy as np

import mcref

MODELS = ["tau_plus_eq22", "ndf_eq17"]


def python_ms(name, theta, inner=5):
    f = getattr(mcref.micrograin, name)
    f(0.5, 0.8, theta[:10])
    best = float("inf")
    for _ in range(inner):
        t0 = time.perf_counter()
        f(0.5, 0.8, theta)
        best = min(best, time.perf_counter() - t0)
    return 1e3 * best


def cpp_ms(binary, name):
    out = subprocess.run([binary, f"--benchmark_filter=BM_{name}$", "--benchmark_format=json",
                          "--benchmark_repetitions=5", "--benchmark_report_aggregates_only=true"],
                         capture_output=True, text=True, check=True).stdout
    runs = json.loads(out)["benchmarks"]
    return [r["real_time"] for r in runs if r.get("aggregate_name") == "median"][0]  # ms


def main():
    binary = sys.argv[1]
    reps = int(sys.argv[2]) if len(sys.argv) > 2 else 6
    theta = np.linspace(0, 1.5, 10**6)
    for name in MODELS:
        ratios, py, cc = [], [], []
        for _ in range(reps):
            p, c = python_ms(name, theta), cpp_ms(binary, name)
            py.append(p), cc.append(c), ratios.append(p / c)
        print(f"{name:16s} python {np.median(py):7.2f} ms  C++ {np.median(cc):7.2f} ms  "
              f"ratio median {np.median(ratios):.3f}  range [{min(ratios):.3f}, {max(ratios):.3f}]  ({reps} alternating reps)")


if __name__ == "__main__":
    main()
