#!/usr/bin/env bash
# Runs the default validation suite: tables, plots and report under out/.
# Extra arguments go to `mcref validate` (e.g. --quiet, --threads 2).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh --target mcref
./build/mcref validate validate/suites/default.toml -o out "$@"
