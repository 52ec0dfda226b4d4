#!/usr/bin/env bash
# Strong scaling of mcref under mpirun (issue #17): the same dataset and the
# same simulate run on 1 and 2 ranks of one thread each; efficiency =
# time(1) / (N x time(N)), best of REPEAT runs. Also rank 0's assembly time
# per entry of a paper-sized entry (32 x 32 x 32 x 32 bins, 4 tables), full
# and lean, timed as `mcref merge` of the finished file (the same reads of
# finished entries and writes as the assembly from the parts).
#   tests/bench/mpi_scaling.sh build/mcref [REPEAT]
set -euo pipefail
mcref=$(realpath "$1")
repeat=${2:-3}
src=$(cd "$(dirname "$0")/../.." && pwd)
mpirun=(mpirun -q --allow-run-as-root --oversubscribe)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
cat > base.toml <<'TOML'
[geometry]
kind = "slab"
[[geometry.layer]]
phase = "sggx_surface"
alpha = 0.5
thickness = 1.0
density = 1.0
albedo = 0.8
[run]
seed = 1
batches = 2
[[measure]]
quantity = "brdf"
theta_i_deg = [20, 40, 60]
theta_o_bins = 8
phi_bins = 8
samples = 200000
TOML
cat > ds.toml <<'TOML'
[dataset]
experiment = "base.toml"
entries = 24
seed = 7
[[parameter]]
key = "geometry.layer.0.thickness"
range = [0.1, 10.0]
distribution = "log_uniform"
TOML
best() {  # best wall seconds of $repeat runs of "$@"
  local b=""
  for ((r = 0; r < repeat; r++)); do
    rm -rf out.h5 out.h5.parts
    local t0 t1
    t0=$(date +%s.%N); "$@" > /dev/null 2>&1; t1=$(date +%s.%N)
    b=$(/usr/bin/python3 -c "print(min(float('${b:-inf}'), $t1 - $t0))")
  done
  echo "$b"
}
for verb in dataset simulate; do
  if [ $verb = dataset ]; then args=(dataset ds.toml -o out.h5 --threads 1 --quiet)
  else args=(simulate "$src/validate/experiments/slab_single_layer.toml" -o out.h5 --threads 1 --quiet
             --set run.batches=8 --set measure.0.samples=200000); fi
  t1=$(best "${mpirun[@]}" -np 1 "$mcref" "${args[@]}")
  t2=$(best "${mpirun[@]}" -np 2 "$mcref" "${args[@]}")
  /usr/bin/python3 -c "print(f'$verb: np=1 {$t1:.2f} s, np=2 {$t2:.2f} s, efficiency {$t1 / (2 * $t2):.3f}')"
done
mkdir paper
cp "$src"/validate/datasets/spongecake_{base,2layer}.toml paper/
sed -i 's/^samples = 25000$/samples = 1/; s/^batches = 4$/batches = 2/' paper/spongecake_base.toml
sed -i 's/^entries = 12000$/entries = 8/' paper/spongecake_2layer.toml
"$mcref" dataset paper/spongecake_2layer.toml -o paper.h5 --quiet
for lean in "" --lean; do
  rm -f merged.h5
  t0=$(date +%s.%N)
  "$mcref" merge paper.h5 -o merged.h5 --quiet $lean
  t1=$(date +%s.%N)
  /usr/bin/python3 -c "print(f'assembly${lean:+ (lean)}: {($t1 - $t0) / 8:.2f} s an entry, $(stat -c %s merged.h5) bytes for 8 entries')"
done
