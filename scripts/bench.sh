#!/usr/bin/env bash
# Runs one criterion bench of deploywatch-sim and writes its figures into
# docs/measured.md (scripts/measured.py bench): criterion's median and 95 %
# interval, and what the bench printed before timing (its accuracy check).
#
#   scripts/bench.sh simulate        one seed001_T01 deployment (target ≤ 1 ms)
#   scripts/bench.sh truss           one seed000 case-2 truss deployment (≤ 5 ms)
#   scripts/bench.sh reliability     200 deployments of the reliability analysis
#   scripts/bench.sh NAME -- ARGS    ARGS passed to criterion (--measurement-time 5)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
name=${1:?usage: scripts/bench.sh simulate|truss|reliability [-- criterion args]}
shift
[ "${1:-}" = "--" ] && shift
log=$(mktemp)
trap 'rm -f "$log"' EXIT
cargo bench -p deploywatch-sim --bench "$name" -- "$@" 2>&1 | tee "$log"
python3 scripts/measured.py bench "$name" "$log"
