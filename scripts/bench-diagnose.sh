#!/usr/bin/env bash
# Times `deploywatch diagnose` (two runs at 100 Hz each unless said):
# - the three bundled example campaigns;
# - the two-cause campaign (seed001 T01 + T02, rig tilt
#   0.05 m/s² at 30° and Coulomb friction 0.8 N·m at joint 1);
# - an unnamed torque (a rub at joint 2 of T01 + T02; torque discovery runs);
# - a 10-run campaign (five T01 and five T02 runs with other noise seeds,
#   Coulomb friction 0.5 N·m at joint 1 and a harness 0.15 N·m/rad at joint 2).
# Prints each wall time and the median of the two-run campaigns, and
# writes them into docs/measured.md (scripts/measured.py diagnose-times).
# Usage: scripts/bench-diagnose.sh   (builds the release binary first)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
cargo build --release -q -p deploywatch-sim
bin=./target/release/deploywatch
mech=data/mechanisms
out=$(mktemp -d)
times=()

# time_diagnose NAME MECH... -- RUN...
time_diagnose() {
    local name=$1; shift
    local args=()
    while [[ $1 != -- ]]; do args+=(--mechanism "$1"); shift; done
    shift
    local start end t
    start=$(date +%s.%N)
    "$bin" diagnose --quiet "${args[@]}" --json "$out/$name.json" "$@" > "$out/$name.txt"
    end=$(date +%s.%N)
    t=$(python3 -c "print(f'{$end - $start:.2f}')")
    echo "$name: $t s ($(head -1 "$out/$name.txt"))" | tee -a "$out/times.log"
    last=$t
}

for spec in a_seed001_eft:seed001_T01:seed001_T02 \
            b_seed000_eft_air_drag:seed000_case1:seed000_case3 \
            c_seed001_friction_harness:seed001_T01:seed001_T02; do
    IFS=: read -r dir m1 m2 <<< "$spec"
    time_diagnose "$dir" "$mech/$m1.toml" "$mech/$m2.toml" -- \
        "data/examples/$dir/$m1.csv" "data/examples/$dir/$m2.csv"
    times+=("$last")
done

simulate() { # MECH OUT SEED EFFECT...
    local m=$1 o=$2 s=$3; shift 3
    local eff=()
    for e in "$@"; do eff+=(--effect "$e"); done
    "$bin" simulate "$mech/$m.toml" --out "$o" --seed "$s" "${eff[@]}" > /dev/null
}

two_cause=(rig_tilt:value=0.05:alpha_deg=30 coulomb_friction:joint=1:value=0.8)
simulate seed001_T01 "$out/tc1.csv" 1 "${two_cause[@]}"
simulate seed001_T02 "$out/tc2.csv" 2 "${two_cause[@]}"
time_diagnose two_cause "$mech/seed001_T01.toml" "$mech/seed001_T02.toml" -- "$out/tc1.csv" "$out/tc2.csv"
times+=("$last")

rub="torque_table:joint=2:angle_deg=0,50,70,90,110,130,180:torque_nm=0,0,0.15,0.3,0.15,0,0"
simulate seed001_T01 "$out/u1.csv" 3 "$rub"
simulate seed001_T02 "$out/u2.csv" 4 "$rub"
time_diagnose unnamed_torque "$mech/seed001_T01.toml" "$mech/seed001_T02.toml" -- "$out/u1.csv" "$out/u2.csv"
times+=("$last")

ten=()
for k in 1 2 3 4 5; do
    for m in seed001_T01 seed001_T02; do
        simulate "$m" "$out/ten_${m}_$k.csv" "$((k * 10))" \
            coulomb_friction:joint=1:value=0.5 harness_stiffness:joint=2:value=0.15
        ten+=("$out/ten_${m}_$k.csv")
    done
done
time_diagnose ten_runs "$mech/seed001_T01.toml" "$mech/seed001_T02.toml" -- "${ten[@]}"

python3 -c "import statistics,sys; print(f'median of the two-run campaigns: {statistics.median(map(float, sys.argv[1:])):.2f} s')" "${times[@]}" | tee -a "$out/times.log"
python3 scripts/measured.py diagnose-times "$out/times.log"
rm -rf "$out"
