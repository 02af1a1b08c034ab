#!/usr/bin/env bash
# Builds the example firmware (firmware-example/) and replays recorded runs
# through it on QEMU's Cortex-M4 board with `deploywatch replay --target qemu`,
# which checks that the MCU's statuses are bit-identical with the host
# simulator's f32 run of the same monitor; and streams a run in real time to
# its serial-link build with `deploywatch hil` (hardware in the loop).
#
# Usage:
#   scripts/firmware.sh build                 firmware ELF + deploywatch, prints the sizes
#   scripts/firmware.sh size                  flash / RAM of the ELF against the budget
#   scripts/firmware.sh panic-check           no panic path linked from the project's code
#   scripts/firmware.sh run IN.bin OUT.bin    run the firmware on QEMU: configuration and
#                                             sample frames IN.bin -> status frames OUT.bin
#                                             (IN.bin: input.bin of `deploywatch replay --keep`)
#   scripts/firmware.sh replay RUN.csv MECH.toml [DIR]
#                                             deploywatch replay --target qemu, frames kept
#                                             in DIR (default target/replay/<set>-<run>)
#   scripts/firmware.sh hil RUN.csv MECH.toml [ARGS...]
#                                             deploywatch hil over TCP to QEMU (real time)
#   scripts/firmware.sh test                  replay every reference mechanism, then the
#                                             real-time serial link on short runs of 3 and
#                                             6 joints (CI)
#
# The toolchain comes from scripts/embedded-toolchain.sh (run it first);
# scripts/embedded-env.sh picks the rustup or the Debian route.
# Environment: QEMU_TIMEOUT (seconds, default 300); DW_HOST_TESTS=0 (`test`
# leaves out the host tests replay and hil, which scripts/test.sh runs in
# its cargo test); DW_HIL_DEADLINES=1
# (the real-time run of `test` fails on a deadline miss; by default it
# reports the misses: on a shared machine they measure the host's
# scheduling of QEMU, not the firmware — docs/firmware.md).
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
fw="$root/firmware-example"
# The firmware's own target directory (its own workspace): firmware-example/target,
# or DW_FIRMWARE_TARGET_DIR.
fw_target=${DW_FIRMWARE_TARGET_DIR:-$fw/target}
fw_bin="$fw_target/thumbv7em-none-eabihf/release"
# One replay firmware per joint count (the monitor's N is the binary's):
# 3 joints is the default, -2 and -6 the others (firmware-example/Cargo.toml).
elf="$fw_bin/deploywatch-firmware-example"
uart_elf="$fw_bin/deploywatch-firmware-uart"
# elf_for JOINTS: the replay firmware of that joint count.
elf_for() {
    if [ "$1" = 3 ]; then echo "$elf"; else echo "$elf-$1"; fi
}
# uart_elf_for JOINTS: the serial-link firmware of that joint count (3 or 6).
uart_elf_for() {
    if [ "$1" = 3 ]; then echo "$uart_elf"; else echo "$uart_elf-$1"; fi
}
deploywatch=  # set by build_host_tool
# The regions memory.x declares (the link fails beyond them; this check
# reports the margin): 60 KiB of flash and 16 KiB of RAM for the replay
# firmware of 2 or 3 joints (docs/performance.md, "Flash, stack and RAM");
# the one of 6 joints has 32 KiB of RAM (firmware-example/memory-6.x).
FLASH_BUDGET=$((60 * 1024))
RAM_BUDGET=$((16 * 1024))
RAM_BUDGET_6=$((32 * 1024))
# The monitor's budgets on the Cortex-M4F (docs/monitor.md §6.1): instructions
# of the sample path Monitor::update (ideal latches / a physical latch), of
# one predict slice (17 slices within 30 % of a 100 MHz M4F at 100 Hz), and
# the stack, for the monitors of up to 3 joints. `test` writes the measured
# figures against them into docs/measured.md (scripts/measured.py) and fails
# when one is not met; those of 6 joints are measured and stated there.
# Ideal latches: 4,800, below the 5,200 of a physical latch: each joint
# carries its own latch thresholds (a wing may mix ideal, plunger and pawl
# latches; docs/firmware.md). (5,200 + 17 x 17,300) x 100 = 29.9 M
# instructions a second: within 30 % of a 100 MHz M4F at 100 Hz. The meter reads SysTick ticks of 5
# instructions (QEMU -icount shift=3), its own cost calibrated to a tick.
UPDATE_BUDGET=4800
UPDATE_BUDGET_PHYSICAL=5200
SLICE_BUDGET=17300
STACK_BUDGET=$((8 * 1024))
# The serial-link build (firmware-example/memory-uart.x): 64 KiB of flash;
# that of 6 joints (memory-uart-6.x) 32 KiB of RAM.
UART_FLASH_BUDGET=$((64 * 1024))

die() { echo "firmware.sh: $*" >&2; exit 1; }

# shellcheck source=scripts/embedded-env.sh
. "$root/scripts/embedded-env.sh" || die "no embedded toolchain: run scripts/embedded-toolchain.sh"

build_firmware() {
    # cargo reads firmware-example/.cargo/config.toml only when run from there.
    # shellcheck disable=SC2086 # DW_BUILD_STD is a list of arguments
    (cd "$fw" && CARGO_TARGET_DIR="$fw_target" dw_cargo build --release $DW_BUILD_STD)
}

build_host_tool() {
    # The host CLI: the test build's binary (scripts/deploywatch-bin.py; the
    # one `cargo test --workspace` runs, so scripts/test.sh compiles nothing
    # again here).
    deploywatch=$(cd "$root" && python3 scripts/deploywatch-bin.py) \
        || die "the host build of deploywatch failed"
    [ -x "$deploywatch" ] || die "no $deploywatch after the build"
}

# size_of ELF FLASH_BUDGET [RAM_BUDGET]: flash and RAM of one ELF against its budget.
size_of() {
    local elf=$1 budget=$2 ram_budget=${3:-$RAM_BUDGET}
    [ -f "$elf" ] || die "no firmware ELF $elf: run scripts/firmware.sh build"
    # Berkeley format: text (flash code + constants), data (flash and RAM),
    # bss (RAM). The stack takes the rest of RAM.
    local text data bss
    read -r text data bss _ < <(arm-none-eabi-size "$elf" | sed -n 2p)
    local flash=$((text + data)) ram=$((data + bss))
    flash_of_last=$flash ram_of_last=$ram
    echo "firmware: $elf"
    printf '  flash %6d B of %6d B (%3d %%)\n' "$flash" "$budget" $((100 * flash / budget))
    printf '  RAM   %6d B of %6d B (%3d %%), static data only; the stack uses the rest\n' \
        "$ram" "$ram_budget" $((100 * ram / ram_budget))
    [ "$flash" -le "$budget" ] && [ "$ram" -le "$ram_budget" ] || die "over the budget"
}

size_report() {
    local rows=() n ram_budget
    for n in 3 2 6; do
        ram_budget=$RAM_BUDGET
        [ "$n" = 6 ] && ram_budget=$RAM_BUDGET_6
        size_of "$(elf_for $n)" "$FLASH_BUDGET" "$ram_budget"
        rows+=("$n:$flash_of_last:$ram_of_last:$FLASH_BUDGET:$ram_budget")
    done
    python3 "$root/scripts/measured.py" firmware-size "${rows[@]}"
    size_of "$uart_elf" "$UART_FLASH_BUDGET"
    size_of "$(uart_elf_for 6)" "$UART_FLASH_BUDGET" "$RAM_BUDGET_6"
}

# joints_of MECH.toml: the mechanism's joint count (its [[panel]] tables).
joints_of() {
    grep -c '^\[\[panel\]\]' "$1"
}

# panic_check: the firmware ELF must link no panic path from the project's
# own code (core/src, firmware-example/src): every call site of a panic entry
# (core::panicking, slice index and length failures, unwrap/expect failures,
# and the outlined stubs that branch to them) is resolved through its inlined
# frames (addr2line -i, the ELF's debug info), and one inside the project's
# sources fails the build. Call sites that are only in dependencies
# (semihosting, cobs, postcard, defmt's reentrancy checks) are counted and
# named, not failed: their panics are theirs to prove.
panic_check() {
    local elf=${1:-$elf}
    [ -f "$elf" ] || die "no firmware ELF $elf: run scripts/firmware.sh build"
    local dis
    dis=$(arm-none-eabi-objdump -d -C --no-show-raw-insn "$elf")
    # Panic entries, then the outlined stubs that branch into one.
    local entries='core::panicking::|core::slice::index::slice_index_fail|len_mismatch_fail|core::option::unwrap_failed|core::option::expect_failed|core::result::unwrap_failed|core::cell::panic_already'
    local stubs
    stubs=$(awk -v re="<($entries)" '
        /^[0-9a-f]+ <.*>:$/ { fn = $2; next }
        fn ~ /^<OUTLINED_FUNCTION/ && $0 ~ re { print substr(fn, 2, length(fn) - 3) }' <<<"$dis" | sort -u | paste -sd'|')
    [ -n "$stubs" ] && entries="$entries|$stubs"
    local sites
    sites=$(awk -v re="[ \t]b[a-z.]*[ \t]+[0-9a-f]+ <($entries)" '
        /^[0-9a-f]+ <.*>:$/ { fn = $2; next }
        $0 ~ re && fn !~ /^<(core::panicking|core::slice::index::slice_index_fail|core::slice::copy_from_slice_impl|OUTLINED_FUNCTION)/ {
            sub(":", "", $1); print $1 }' <<<"$dis")
    local ours=0 theirs=0 where
    local -A deps=()
    for a in $sites; do
        # The innermost frame outside Rust's own library owns the panic.
        where=$(arm-none-eabi-addr2line -e "$elf" -i -a "0x$a" | tail -n +2 \
            | grep -vE "(/rustlib/src/rust/library/|^/rustc/)" | head -1 || true)
        if grep -qE "^($root/core/src|$fw/src)/" <<<"$where"; then
            ours=$((ours + 1))
            echo "firmware.sh: a panic path in the project's code at 0x$a:" >&2
            arm-none-eabi-addr2line -e "$elf" -f -i -C -a "0x$a" | tail -n +2 | paste - - | sed 's/^/    /' >&2
        else
            theirs=$((theirs + 1))
            local dep
            dep=$(grep -oE 'registry/src/[^/]+/[^/]+' <<<"$where" | sed 's#.*/##' || true)
            deps[${dep:-unattributed@0x$a}]=1
        fi
    done
    [ "$ours" -eq 0 ] || die "$ours panic path(s) linked from core/src or firmware-example/src"
    echo "  panic paths ($(basename "$elf")): none from core/src or firmware-example/src; $theirs call site(s) in dependencies: ${!deps[*]}"
}

# qemu_exec IN OUT [ELF]: runs the firmware (of 3 joints unless ELF) on IN, writes OUT and returns
# QEMU's exit status (the firmware's); the defmt log goes to stdout, decoded
# by defmt-print when it is installed.
qemu_exec() {
    local in out elf=${3:-$elf}
    in=$(realpath "$1")
    out=$(realpath -m "$2")
    [ -f "$in" ] || die "no input file $1"
    case "$in$out" in
        *[[:space:]]*) die "paths with spaces cannot be semihosting arguments: $in $out" ;;
    esac
    # -semihosting-config takes commas doubled inside a value.
    local args="arg=deploywatch-firmware-example,arg=${in//,/,,},arg=${out//,/,,}"
    # -icount shift=3: one instruction is 8 ns of virtual time (5 a SysTick
    # tick), which the firmware's instruction count of Monitor::update
    # relies on; sleep=off: an idle wfi skips to the next tick at once.
    local qemu=(qemu-system-arm -cpu cortex-m4 -machine mps2-an386 -nographic -icount shift=3,sleep=off
        -semihosting-config "enable=on,target=native,$args" -kernel "$elf")
    local status=0
    if command -v defmt-print >/dev/null 2>&1; then
        set +e
        timeout "${QEMU_TIMEOUT:-300}" "${qemu[@]}" | defmt-print -e "$elf"
        local st=("${PIPESTATUS[@]}")
        set -e
        status=${st[0]}
    else
        local log="${out%.*}.defmt"
        timeout "${QEMU_TIMEOUT:-300}" "${qemu[@]}" >"$log" || status=$?
        echo "(defmt-print not installed: raw log in $log; decode with defmt-print -e $elf < $log)"
    fi
    return "$status"
}

qemu_run() {
    local status=0
    qemu_exec "$@" || status=$?
    [ "$status" -eq 0 ] || die "the firmware failed on $1 (QEMU exit $status; 124 is the timeout)"
}

# replay RUN.csv MECH.toml [DIR]: deploywatch replay --target qemu (exit 1
# unless bit-identical with the host), frames and status CSV kept in DIR.
replay() {
    local csv=$1 mech=$2 dir=${3:-}
    [ -f "$csv" ] || die "no run file $csv"
    [ -f "$mech" ] || die "no mechanism file $mech"
    if [ -z "$dir" ]; then
        dir="$root/target/replay/$(basename "$(dirname "$csv")")-$(basename "${csv%.*}")"
    fi
    mkdir -p "$dir"
    # The firmware's log (instruction counts, stack) goes to stderr and to
    # DIR/replay.log, which scripts/measured.py reads.
    # The replay firmware built for the mechanism's joint count.
    "$deploywatch" replay "$csv" --mechanism "$mech" --target qemu --elf "$(elf_for "$(joints_of "$mech")")" \
        --keep "$dir" --out "$dir/status.csv" --timeout "${QEMU_TIMEOUT:-300}" \
        2> >(tee "$dir/replay.log" >&2) \
        || die "replay of $csv failed"
}

# hil RUN.csv MECH.toml [ARGS...]: deploywatch hil over TCP to QEMU (the
# serial-link firmware), in real time.
hil() {
    local csv=$1 mech=$2
    shift 2
    "$deploywatch" hil "$csv" --mechanism "$mech" --elf "$(uart_elf_for "$(joints_of "$mech")")" "$@" \
        || die "hil of $csv failed"
}

cmd=${1:-}
case "$cmd" in
    build)
        build_firmware
        build_host_tool
        size_report
        for n in 3 2 6; do panic_check "$(elf_for $n)"; done
        panic_check "$uart_elf"
        panic_check "$(uart_elf_for 6)"
        ;;
    size)
        size_report
        ;;
    panic-check)
        for n in 3 2 6; do panic_check "$(elf_for $n)"; done
        panic_check "$uart_elf"
        panic_check "$(uart_elf_for 6)"
        ;;
    hil)
        [ $# -ge 3 ] || die "usage: scripts/firmware.sh hil RUN.csv MECH.toml [ARGS...]"
        build_firmware
        build_host_tool
        shift
        hil "$@"
        ;;
    run)
        [ $# -eq 3 ] || die "usage: scripts/firmware.sh run IN.bin OUT.bin"
        build_firmware
        qemu_run "$2" "$3"
        ;;
    replay)
        [ $# -ge 3 ] && [ $# -le 4 ] || die "usage: scripts/firmware.sh replay RUN.csv MECH.toml [DIR]"
        build_firmware
        build_host_tool
        replay "$2" "$3" "${4:-}"
        ;;
    test)
        build_firmware
        build_host_tool
        size_report
        for n in 3 2 6; do panic_check "$(elf_for $n)"; done
        panic_check "$uart_elf"
        panic_check "$(uart_elf_for 6)"
        # The replay protocol and the firmware's loop, on the host; the
        # serial link's loop on lossy streams and the latch escapes.
        # DW_HOST_TESTS=0 leaves them out: scripts/test.sh has run them in
        # its `cargo test --workspace`; here cargo built part of the
        # workspace again for them, minutes of the CI's two cores.
        if [ "${DW_HOST_TESTS:-1}" = 0 ]; then
            echo "firmware: the host tests replay and hil left out (DW_HOST_TESTS=0: run by cargo test --workspace)"
        else
            (cd "$root" && cargo test --quiet --workspace --locked --test replay --test hil)
        fi
        # Every reference mechanism (data/mechanisms/: seed 000 cases 1 and 3,
        # 2 joints, on the firmware of 2; seed 001 T01 and T02, 3 joints, on
        # that of 3), nominal and with friction
        # (data/reference/), then measured-like runs (noise, quantisation,
        # friction) of the seed 001 mechanisms, and the physical-latch runs.
        for ref in "$root"/data/reference/*.csv; do
            name=$(basename "$ref" .csv)        # e.g. seed001_T01_eft
            replay "$ref" "$root/data/mechanisms/${name%_*}.toml"
        done
        for set in a_seed001_eft c_seed001_friction_harness; do
            for t in T01 T02; do
                replay "$root/data/examples/$set/seed001_$t.csv" "$root/data/mechanisms/seed001_$t.toml"
            done
        done
        # The simulator's physical-latch runs of 3 joints (bounces, escapes),
        # the monitor configured with their physical latch.
        replay "$root/data/examples/latch_clean_bounce/seed001_T02.csv" \
            "$root/data/mechanisms/seed001_T02_physical_latch.toml"
        replay "$root/data/examples/latch_escape_never/seed001_T01.csv" \
            "$root/data/mechanisms/seed001_T01_physical_latch.toml"
        # Wings of 4 and 6 panels (data/mechanisms/wing4_*, wing6_*): the
        # 6-joint runs on the firmware built for 6 joints; the 4-joint run on
        # the firmware of 3, which must refuse it (exit 1, the joint count named).
        for run in "$root"/data/examples/wing6/*.csv; do
            replay "$run" "$root/data/mechanisms/$(basename "${run%.csv}").toml"
        done
        w4="$root/data/examples/wing4/wing4_ideal.csv"
        wrong="$root/target/replay/wrong-joint-count"
        mkdir -p "$wrong"
        "$deploywatch" replay "$w4" --mechanism "$root/data/mechanisms/wing4_ideal.toml" \
            --target host --keep "$wrong" -q >/dev/null
        status=0
        qemu_exec "$wrong/input.bin" "$wrong/qemu.bin" >"$wrong/qemu.log" 2>&1 || status=$?
        [ "$status" -eq 1 ] || die "a 4-joint input to the 3-joint firmware gave QEMU exit $status, expected 1"
        grep -q "this firmware is built for 3" "$wrong/qemu.log" \
            || die "the 3-joint firmware did not name the joint count of a 4-joint input"
        echo "4-joint input to the 3-joint firmware: refused by name, exit 1, as it should"
        # A damaged input must fail the firmware with exit 1, not hang or
        # write a partial file as if all were well.
        bad="$root/target/replay/truncated"
        mkdir -p "$bad"
        input="$root/target/replay/reference-seed001_T01_nominal/input.bin"
        head -c "$(($(stat -c %s "$input") - 2))" "$input" >"$bad/input.bin"
        status=0
        qemu_exec "$bad/input.bin" "$bad/qemu.bin" || status=$?
        [ "$status" -eq 1 ] || die "a truncated input gave QEMU exit $status, expected 1"
        echo "truncated input: the firmware reports it and exits 1, as it should"
        python3 "$root/scripts/measured.py" firmware-replays "$root/target/replay" \
            "$UPDATE_BUDGET" "$UPDATE_BUDGET_PHYSICAL" "$SLICE_BUDGET" "$STACK_BUDGET"
        echo "measured figures: docs/measured.md"
        # Hardware in the loop over TCP, in real time, on one short 100 Hz
        # run: every status bit-identical with the host core (exit 1
        # otherwise), deadline misses reported; then 1 % of the frames dropped and 1 %
        # corrupted on the way in: counted exactly, the statuses those of
        # the host core on the samples that arrived.
        t01="$root/data/examples/a_seed001_eft/seed001_T01.csv"
        # Deadline misses are reported; DW_HIL_DEADLINES=1 fails on one (a
        # quiet host or a board: on a shared CI machine a miss measures its
        # scheduling of QEMU, and a timed check there is not a test).
        deadlines=()
        if [ "${DW_HIL_DEADLINES:-0}" = 1 ]; then
            deadlines=(--require-deadlines)
        fi
        hil "$t01" "$root/data/mechanisms/seed001_T01.toml" --duration 2 "${deadlines[@]}"
        hil "$t01" "$root/data/mechanisms/seed001_T01.toml" --drop 0.01 --corrupt 0.01 --seed 3 -q
        # Six joints on the serial-link build of 6: the six-panel wing's
        # whole run, every status bit-identical with the host core's and
        # the frames counted exactly (exit 1 otherwise); its deadline
        # misses are reported, not required, until measured on a quiet host.
        hil "$root/data/examples/wing6/wing6_ideal.csv" "$root/data/mechanisms/wing6_ideal.toml"
        # The Python twin (`deploywatch.hil`) on the same firmware, when the
        # package's environment is made and holds the package
        # (scripts/python-env.sh). DW_HIL_PYTHON=0 leaves it out: scripts/test.sh
        # runs it after both its lanes, since its other lane makes .venv.
        if [ "${DW_HIL_PYTHON:-1}" = 0 ]; then
            echo "hil: the Python twin left out (DW_HIL_PYTHON=0)"
        elif [ -x "$root/.venv/bin/pytest" ] && "$root/.venv/bin/python" -c 'import deploywatch' 2>/dev/null; then
            (cd "$root" && DW_HIL_ELF="$uart_elf" .venv/bin/pytest -q python/tests/test_hil.py)
        else
            echo "hil: no .venv holding the package (scripts/python-env.sh): the Python twin not run"
        fi
        ;;
    *)
        sed -n '2,20p' "$0" >&2
        exit 2
        ;;
esac
