#!/usr/bin/env bash
# Times `deploywatch diagnose` on the three bundled example campaigns (two
# runs at 100 Hz each) and prints each wall time and the median.
# Usage: scripts/bench-diagnose.sh   (builds the release binary first)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
cargo build --release -q -p deploywatch-sim
out=$(mktemp -d)
times=()
for spec in a_seed001_eft:seed001_T01:seed001_T02 \
            b_seed000_eft_air_drag:seed000_case1:seed000_case3 \
            c_seed001_friction_harness:seed001_T01:seed001_T02; do
    IFS=: read -r dir m1 m2 <<< "$spec"
    start=$(date +%s.%N)
    ./target/release/deploywatch diagnose --quiet \
        --mechanism "data/mechanisms/$m1.toml" --mechanism "data/mechanisms/$m2.toml" \
        --json "$out/$dir.json" "data/examples/$dir/$m1.csv" "data/examples/$dir/$m2.csv" > /dev/null
    end=$(date +%s.%N)
    t=$(python3 -c "print(f'{$end - $start:.2f}')")
    echo "$dir: $t s"
    times+=("$t")
done
python3 -c "import statistics,sys; print(f'median: {statistics.median(map(float, sys.argv[1:])):.2f} s')" "${times[@]}"
rm -rf "$out"
