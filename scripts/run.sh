#!/usr/bin/env bash
# Runs the default validation suite: tables and results.json under out/, then
# the plots and out/report.html rendered from them (scripts/plot_validation.py,
# scripts/report.py; either can be rerun alone, without simulating).
# Extra arguments go to `mcref validate` (e.g. --quiet, --threads 2, --case 'fig9_*').
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh --target mcref
status=0
./build/mcref validate validate/suites/default.toml -o out "$@" || status=$?
if [ "$status" -le 1 ]; then  # 0: all pass, 1: some check failed; 2: bad input, nothing written
  quiet=()
  for a in "$@"; do case "$a" in --quiet | -q) quiet=(--quiet) ;; esac; done
  /usr/bin/python3 scripts/plot_validation.py out "${quiet[@]}"
  /usr/bin/python3 scripts/report.py out "${quiet[@]}"
fi
exit "$status"
