#!/usr/bin/env bash
# Runs the default validation suite: tables and results.json under out/, then
# SpongeCake's multiple-scattering approximation at reduced scale (datasets, fits,
# networks, figures and summary.json under out/spongecake/; scripts/spongecake/stage.py,
# validate/spongecake_stage.toml; steps up to date are skipped), then the
# plots and out/report.html rendered from them (scripts/plot_validation.py,
# scripts/report.py; either can be rerun alone, without simulating).
# Extra arguments go to `mcref validate` (e.g. --quiet, --threads 2, --case 'fig9_*');
# --quiet and --threads go to the SpongeCake stage too, and --case leaves it out.
set -euo pipefail
for a in "$@"; do
  if [ "$a" = --help ] || [ "$a" = -h ]; then  # (validate --help exits 0: the stages below would run)
    sed -n '2,/^set /p' "$0" | sed '$d; s/^# \{0,1\}//'
    exit 0
  fi
done
cd "$(dirname "$0")/.."
bash scripts/build.sh --target mcref
status=0
./build/mcref validate validate/suites/default.toml -o out "$@" || status=$?
if [ "$status" -le 1 ]; then  # 0: no check failed, 1: some did; 2: bad input, 3: an error while running
  quiet=() stage=(--jobs 2) run_stage=1
  args=("$@")
  for ((k = 0; k < ${#args[@]}; k++)); do
    case "${args[k]}" in
      --quiet | -q) quiet=(--quiet) ;;
      --threads) stage+=(--threads "${args[k + 1]:-}") ;;
      --case) run_stage=0 ;;
    esac
  done
  if [ "$run_stage" = 1 ]; then
    /usr/bin/python3 scripts/spongecake/stage.py validate/spongecake_stage.toml out/spongecake \
      --mcref build/mcref "${stage[@]}" "${quiet[@]}" || status=$?
  fi
  /usr/bin/python3 scripts/plot_validation.py out "${quiet[@]}"
  /usr/bin/python3 scripts/report.py out "${quiet[@]}"
fi
exit "$status"
