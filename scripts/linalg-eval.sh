#!/usr/bin/env bash
# core/src/physics/linalg.rs against nalgebra's fixed-size, no_std
# SMatrix/SVector, on the Cortex-M4F (thumbv7em-none-eabihf) under QEMU.
# The experiment is experiments/linalg-nalgebra/ (its own workspace, excluded
# from the root one); docs/performance.md, "nalgebra for linalg.rs", has the
# results and the decision.
#
# Usage:
#   scripts/linalg-eval.sh [PROFILE]     instructions per call (QEMU, -icount
#                                        shift=0), agreement, flash, panic sites;
#                                        PROFILE: release (default: the
#                                        firmware's opt-level "z", fat LTO) or
#                                        release-o3 (the same at opt-level 3)
#   scripts/linalg-eval.sh compile-cost  what nalgebra adds to the build: crates
#                                        and the wall time of compiling them (a
#                                        fresh target dir; minutes)
#   scripts/linalg-eval.sh firmware [RUN.csv MECH.toml ...]
#                                        the whole firmware with nalgebra in
#                                        linalg.rs: copies core/ and
#                                        firmware-example/ to a scratch folder,
#                                        builds them as they are and with
#                                        experiments/linalg-nalgebra/firmware/linalg.rs
#                                        in the copy's core; prints both flash
#                                        figures and, for each run given (default:
#                                        the T01 and case-1 references), both
#                                        firmwares' Monitor::update / predict
#                                        counts on the same input (needs the host
#                                        tool: cargo build --release -p deploywatch-sim)
#
# Needs the embedded toolchain (scripts/embedded-toolchain.sh). Not part of
# scripts/test.sh: it is an evaluation, rerun by hand.
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
exp="$root/experiments/linalg-nalgebra"
out="$exp/target/linalg-eval"

die() { echo "linalg-eval.sh: $*" >&2; exit 1; }

# shellcheck source=scripts/embedded-env.sh
. "$root/scripts/embedded-env.sh" || die "no embedded toolchain: run scripts/embedded-toolchain.sh"

# build PROFILE FEATURES [TARGET_DIR]: cargo reads the experiment's
# .cargo/config.toml only when run from its folder.
build() {
    local profile=$1 features=$2 dir=${3:-$exp/target}
    # shellcheck disable=SC2086 # DW_BUILD_STD is a list of arguments
    (cd "$exp" && CARGO_TARGET_DIR="$dir" dw_cargo build --quiet --profile "$profile" \
        ${features:+--features "$features"} $DW_BUILD_STD)
}

elf_dir() { echo "$exp/target/$DW_TARGET/$1"; }

flash_of() {
    local text data
    read -r text data _ < <(arm-none-eabi-size "$1" | sed -n 2p)
    echo $((text + data))
}

# Branches to a panic entry (core::panicking, bounds/slice/unwrap failures),
# outside those entries themselves: the call sites a panic can come from.
panic_sites() {
    arm-none-eabi-objdump -d -C --no-show-raw-insn "$1" | awk '
        /^[0-9a-f]+ <.*>:$/ { fn = $2; next }
        $0 ~ /[ \t]b[a-z.]*[ \t]+[0-9a-f]+ <(core::panicking|core::slice::index|core::option::unwrap_failed|core::option::expect_failed|core::result::unwrap_failed)/ \
            && fn !~ /^<(core::panicking|core::slice::index|core::option|core::result)/ { n++ }
        END { print n + 0 }'
}

# Bytes of the symbols (nm -S) whose demangled name matches a pattern.
sym_bytes() {
    local sum=0 size
    while read -r size; do
        sum=$((sum + 16#$size))
    done < <(arm-none-eabi-nm -S -C "$1" | grep -E "$2" | awk 'NF >= 4 { print $2 }')
    echo "$sum"
}

evaluate() {
    local profile=$1
    mkdir -p "$out"
    echo "== instructions per call and agreement ($profile; QEMU mps2-an386, -icount shift=0)"
    build "$profile" bench
    local bench
    bench="$(elf_dir "$profile")/bench"
    timeout "${QEMU_TIMEOUT:-300}" qemu-system-arm -cpu cortex-m4 -machine mps2-an386 -nographic \
        -icount shift=0 -semihosting-config enable=on,target=native -kernel "$bench" \
        | tee "$out/bench-$profile.txt"
    [ "${PIPESTATUS[0]}" -eq 0 ] || die "the bench failed (agreement or a panic): $out/bench-$profile.txt"

    echo
    echo "== flash ($profile): footprint binaries that differ only in the implementation they link"
    echo "   (each calls solve, articulated_inertias, articulated_inertia, mat_vec for N = 2 and 3, f32)"
    echo
    echo "| build | flash (text + data) | linalg's share | panic call sites |"
    echo "|---|---|---|---|"
    local base=
    for v in none impl-core impl-nalgebra; do
        local features=$v
        [ "$v" = none ] && features=
        build "$profile" "$features"
        cp "$(elf_dir "$profile")/footprint" "$out/footprint-$profile-$v"
        local f
        f=$(flash_of "$out/footprint-$profile-$v")
        [ -n "$base" ] || base=$f
        printf '| %s | %d B | %+d B | %d |\n' "$v" "$f" $((f - base)) "$(panic_sites "$out/footprint-$profile-$v")"
    done

    echo
    echo "== symbols of the bench binary ($profile), arm-none-eabi-nm -S (LU included; out-of-line helpers counted once)"
    echo
    echo "| group | bytes |"
    echo "|---|---|"
    printf '| core: linalg_nalgebra::core_impl + deploywatch_core::linalg | %d |\n' \
        "$(sym_bytes "$bench" 'linalg_nalgebra::core_impl::|deploywatch_core::linalg::')"
    printf '| nalgebra: linalg_nalgebra::nalgebra_impl + nalgebra + simba + libm sqrt | %d |\n' \
        "$(sym_bytes "$bench" 'linalg_nalgebra::nalgebra_impl::|[ <]nalgebra::|simba::|libm::math::generic::sqrt')"
    printf '|   of which nalgebra_impl::solve_lu2 + solve_lu3 | %d |\n' \
        "$(sym_bytes "$bench" 'nalgebra_impl::solve_lu')"
    printf '|   of which the square root (simba try_sqrt, libm sqrtf and its table) | %d |\n' \
        "$(sym_bytes "$bench" 'try_sqrt|libm::math::generic::sqrt')"
    echo
    echo "largest symbols:"
    local size name
    arm-none-eabi-nm --size-sort -S -C "$bench" \
        | grep -E 'linalg_nalgebra::|deploywatch_core::linalg::|Cholesky|simba::|libm::math::generic::sqrt' \
        | awk '{ print $2, substr($0, index($0, $4)) }' \
        | while read -r size name; do printf '  %6d  %s\n' $((16#$size)) "$name"; done | sort -rn | head -20
}

compile_cost() {
    local dir="$out/compile-cost"
    # A target dir of its own, so that the timings are of a fresh build.
    if [ -d "$dir" ]; then
        rm -rf "$dir"
    fi
    echo "== what nalgebra adds to the thumbv7em build (fresh target dir $dir)"
    echo "crates, without and with impl-nalgebra (normal dependencies):"
    local without with
    without=$(cd "$exp" && dw_cargo tree -e normal --prefix none --target "$DW_TARGET" | sed "s/ (\*)//" | sort -u)
    with=$(cd "$exp" && dw_cargo tree -e normal --prefix none --target "$DW_TARGET" --features impl-nalgebra | sed "s/ (\*)//" | sort -u)
    comm -13 <(echo "$without") <(echo "$with") | sed "s/ (\*)//" | sort -u | sed "s/^/  + /"
    local t0 t1 t2
    t0=$(date +%s.%N)
    build release impl-core "$dir"
    t1=$(date +%s.%N)
    build release impl-core,impl-nalgebra "$dir"
    t2=$(date +%s.%N)
    printf 'release build, core only (build-std core, deploywatch-core, cortex-m): %.1f s\n' "$(echo "$t1 - $t0" | bc)"
    printf 'then adding impl-nalgebra (nalgebra and its crates, relink):          %.1f s\n' "$(echo "$t2 - $t1" | bc)"
    echo "(wall time on this machine, load average $(cut -d' ' -f1-3 /proc/loadavg))"
}

# firmware_eval [RUN.csv MECH.toml]...: see the header.
firmware_eval() {
    # Outside experiments/linalg-nalgebra/: cargo would merge its .cargo/config.toml
    # (rustflags) with the firmware's.
    local scratch="$root/target/linalg-eval/firmware"
    # A fresh copy of the sources; the target dir is kept between runs.
    rm -rf "$scratch/core" "$scratch/firmware-example"
    mkdir -p "$scratch"
    # The working tree's core/ and firmware-example/ (not their targets), and a
    # memory.x with room to link what does not fit: the flash is measured by
    # arm-none-eabi-size against the 64 KiB budget, not by the link.
    tar -C "$root" --exclude=./firmware-example/target --exclude=./core/target \
        -cf - core firmware-example | tar -C "$scratch" -xf -
    sed 's/LENGTH = 64K/LENGTH = 128K/' "$root/memory.x" >"$scratch/memory.x"
    # The root manifest, for what core/Cargo.toml inherits from the workspace.
    sed 's/^members = .*/members = ["core"]/' "$root/Cargo.toml" >"$scratch/Cargo.toml"
    local fw="$scratch/firmware-example" elf
    elf="$scratch/target/$DW_TARGET/release/deploywatch-firmware-example"
    fw_build() {
        # shellcheck disable=SC2086 # DW_BUILD_STD is a list of arguments
        (cd "$fw" && CARGO_TARGET_DIR="$scratch/target" dw_cargo build --quiet --release $DW_BUILD_STD)
    }
    echo "== the firmware as it is (a copy of core/ and firmware-example/)"
    fw_build
    cp "$elf" "$out/firmware-core.elf"
    echo "== the firmware with nalgebra's Cholesky in linalg.rs"
    cp "$exp/firmware/linalg.rs" "$scratch/core/src/physics/linalg.rs"
    sed -i 's/^\[dependencies\]$/[dependencies]\nnalgebra = { version = "0.34", default-features = false, features = ["libm"] }/' \
        "$scratch/core/Cargo.toml"
    fw_build
    cp "$elf" "$out/firmware-nalgebra.elf"
    echo
    echo "| firmware | flash (text + data) | of 65,536 B | panic call sites |"
    echo "|---|---|---|---|"
    local v f
    for v in core nalgebra; do
        f=$(flash_of "$out/firmware-$v.elf")
        printf '| linalg.rs: %s | %d B | %+d B | %d |\n' "$v" "$f" $((f - 65536)) "$(panic_sites "$out/firmware-$v.elf")"
    done
    [ $# -gt 0 ] || set -- \
        "$root/data/reference/seed001_T01_eft.csv" "$root/data/mechanisms/seed001_T01.toml" \
        "$root/data/reference/seed000_case1_eft.csv" "$root/data/mechanisms/seed000_case1.toml"
    local dir deploywatch
    dir=$(cd "$root" && cargo metadata --format-version 1 --no-deps \
        | sed -n 's/.*"target_directory":"\([^"]*\)".*/\1/p')
    deploywatch="${dir:-$root/target}/release/deploywatch"
    if [ ! -x "$deploywatch" ]; then
        echo "(no $deploywatch: cargo build --release -p deploywatch-sim for the instruction counts)"
        return 0
    fi
    while [ $# -ge 2 ]; do
        local run=$1 mech=$2 keep
        shift 2
        keep="$out/replay-$(basename "${run%.*}")"
        mkdir -p "$keep"
        "$deploywatch" replay "$run" --mechanism "$mech" --keep "$keep" --quiet >/dev/null
        echo
        echo "$(basename "$run"): the same input.bin through both firmwares (QEMU -icount shift=0)"
        for v in core nalgebra; do
            local args="arg=fw,arg=$keep/input.bin,arg=$keep/qemu-$v.bin"
            timeout "${QEMU_TIMEOUT:-300}" qemu-system-arm -cpu cortex-m4 -machine mps2-an386 -nographic \
                -icount shift=0 -semihosting-config "enable=on,target=native,$args" \
                -kernel "$out/firmware-$v.elf" | defmt-print -e "$out/firmware-$v.elf" \
                | grep -E 'Monitor::update|predict|stack' | sed "s/^/  $v: /"
            if cmp -s "$keep/qemu-$v.bin" "$keep/host.bin"; then
                echo "  $v: status frames bit-identical with the host's f32 run"
            else
                echo "  $v: status frames differ from the host's f32 run (the host runs the core's L D Lᵀ)"
            fi
        done
    done
}

case "${1:-release}" in
    release | release-o3) evaluate "${1:-release}" ;;
    compile-cost) compile_cost ;;
    firmware)
        shift
        firmware_eval "$@"
        ;;
    *)
        sed -n '2,31p' "$0" >&2
        exit 2
        ;;
esac
