#!/usr/bin/env bash
# The closed-form check of `deploywatch reliability` (docs/reliability.md):
# one panel on a linear spring with a Coulomb friction T_C ~ N(mu, 0.1 N·m)
# fails to latch iff T_C > T*. T* is found by bisection with
# `deploywatch simulate` (a run that latches only by creeping, which
# simulate says, counts as not latched: reliability's deployments hold a
# stalled joint, docs/spec/physics.md §4a "Creep"), mu is set for an exact
# probability P, and the
# estimate of METHOD is printed beside the exact normal tail, with its wall time.
#
#   scripts/reliability-closed-form.sh [P] [METHOD] [SAMPLES] [SEED]
#   scripts/reliability-closed-form.sh 1e-6 subset 2000 0
#   scripts/reliability-closed-form.sh 1e-2 mc 20000 0
#
# The binary is $DEPLOYWATCH when set (scripts/doc-examples.py sets it to the
# test build's, which is optimised too), else the release build, built first.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
p=${1:-1e-6}
method=${2:-subset}
samples=${3:-2000}
seed=${4:-0}
if [ -n "${DEPLOYWATCH:-}" ]; then
    dw=$DEPLOYWATCH
else
    cargo build -q --release --locked -p deploywatch-sim --bin deploywatch
    dw=${CARGO_TARGET_DIR:-target}/release/deploywatch
fi
mech=data/mechanisms/reliability_one_panel.toml
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
latches() {
    local said
    said=$("$dw" simulate "$mech" --out "$tmp/run.csv" --no-noise -q \
        --effect "coulomb_friction:joint=1:value=$1")
    [[ $said == *"joint 1: latched at"* && $said != *"latched only by creeping"* ]]
}
lo=0 hi=5
for _ in $(seq 40); do
    mid=$(python3 -c "print(($lo + $hi) / 2)")
    if latches "$mid"; then lo=$mid; else hi=$mid; fi
done
read -r tstar mu exact < <(python3 -c "
from statistics import NormalDist
t = ($lo + $hi) / 2; sd = 0.1
mu = t + sd * NormalDist().inv_cdf($p)
print(t, repr(mu), 1 - NormalDist().cdf((t - mu) / sd))")
echo "T* = $tstar N·m (bisection with deploywatch simulate); mu = $mu N·m; exact P = $exact"
start=$(date +%s.%N)
"$dw" reliability "$mech" --vary "coulomb_friction:joint=1:normal($mu,0.1)" --fail not_latched \
    --method "$method" --samples "$samples" --seed "$seed" --json "$tmp/r.json" -q
end=$(date +%s.%N)
python3 -c "
import json
r = json.load(open('$tmp/r.json'))
e = $exact
lo, hi = r['ci95']
print(f\"{r['method']}: p = {r['p_fail']:.4e}, exact {e:.4e}, ratio {r['p_fail'] / e:.3f}, \"
      f\"c.o.v. {r['cov']:.3f}, 95 % [{lo:.4e}, {hi:.4e}] {'holds' if lo <= e <= hi else 'MISSES'} the exact value, \"
      f\"{r['simulations']} deployments, {$end - $start:.2f} s wall\")"
