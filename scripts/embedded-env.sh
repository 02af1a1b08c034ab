# shellcheck shell=bash
# Source this file (`. scripts/embedded-env.sh`) to get the environment that
# builds deploywatch for the Cortex-M4F target (thumbv7em-none-eabihf).
# scripts/embedded-toolchain.sh installs what it needs; this file installs
# nothing and only looks at what is there.
#
# It sets:
#   DW_TARGET        thumbv7em-none-eabihf
#   DW_ROUTE         "rustup" or "debian"
#   DW_CARGO         the cargo to run
#   DW_BUILD_STD     extra cargo arguments (empty on the rustup route)
#   RUSTC            (debian route) /usr/bin/rustc, so that cargo does not pick
#                    the rustup proxy that is earlier on PATH
#   RUSTC_BOOTSTRAP  (debian route) 1, see below
# and returns non-zero (without exiting the caller's shell) when neither route
# is usable.
#
# Two routes, chosen in this order:
#  1. rustup, when `rustup target list --installed` has the target: its
#     precompiled `core` is used as it is.
#  2. Debian's rustc-web/cargo-web with rust-web-src: Debian ships no
#     precompiled `core` for thumbv7em-none-eabihf, so `core` and
#     `compiler_builtins` are compiled from the shipped library source with
#     cargo's `-Zbuild-std`. That flag is unstable: RUSTC_BOOTSTRAP=1 lets a
#     stable compiler accept it. It is set for these builds only (never
#     exported to the host build), and nothing else in the project uses an
#     unstable feature, so the code stays stable Rust; the rustup route shows
#     it by building the same code without the flag.

DW_TARGET=thumbv7em-none-eabihf
DW_ROUTE=
DW_CARGO=
DW_BUILD_STD=
export DW_TARGET

dw_env_detect() {
    if command -v rustup >/dev/null 2>&1 \
        && rustup target list --installed 2>/dev/null | grep -qx "$DW_TARGET"; then
        DW_ROUTE=rustup
        DW_CARGO=$(command -v cargo)
        DW_BUILD_STD=
        unset RUSTC RUSTC_BOOTSTRAP
        return 0
    fi
    if [ -x /usr/bin/rustc ] && [ -x /usr/bin/cargo ] \
        && [ -d "$(/usr/bin/rustc --print sysroot 2>/dev/null)/lib/rustlib/src/rust/library/core" ]; then
        DW_ROUTE=debian
        DW_CARGO=/usr/bin/cargo
        DW_BUILD_STD="-Zbuild-std=core,compiler_builtins -Zbuild-std-features=compiler-builtins-mem"
        RUSTC=/usr/bin/rustc
        # Unstable -Zbuild-std on a stable compiler: see the comment at the top.
        RUSTC_BOOTSTRAP=1
        export RUSTC RUSTC_BOOTSTRAP
        return 0
    fi
    echo "embedded-env: no toolchain for $DW_TARGET: run scripts/embedded-toolchain.sh" >&2
    return 1
}

dw_env_print() {
    echo "route:       $DW_ROUTE"
    echo "cargo:       $DW_CARGO ($("$DW_CARGO" --version 2>/dev/null))"
    if [ "$DW_ROUTE" = debian ]; then
        echo "rustc:       $RUSTC ($("$RUSTC" --version 2>/dev/null))"
        echo "env:         RUSTC=$RUSTC RUSTC_BOOTSTRAP=$RUSTC_BOOTSTRAP"
    else
        echo "rustc:       $(command -v rustc) ($(rustc --version 2>/dev/null))"
    fi
    echo "build:       $DW_CARGO build --release --target $DW_TARGET $DW_BUILD_STD"
    for t in arm-none-eabi-ld arm-none-eabi-size qemu-system-arm defmt-print; do
        printf '%-12s %s\n' "$t:" "$(command -v "$t" || echo 'not found')"
    done
}

export DW_ROUTE DW_CARGO DW_BUILD_STD
dw_env_detect && export DW_ROUTE DW_CARGO DW_BUILD_STD
