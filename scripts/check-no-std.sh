#!/usr/bin/env bash
# Proves that deploywatch-core is no_std: builds it for the Cortex-M4F target
# (thumbv7em-none-eabihf, which has no std) with no features, then with each
# of its features alone. A dependency or dev-dependency that pulled in std
# would fail this build (resolver 2 keeps dev-dependencies' features out).
#
# The features are read from the manifest when the script runs, so a new
# feature is checked without editing this file.
#
# Usage: scripts/check-no-std.sh   (after scripts/embedded-toolchain.sh)
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"

# shellcheck source=scripts/embedded-env.sh
. scripts/embedded-env.sh || { echo "check-no-std: run scripts/embedded-toolchain.sh first" >&2; exit 1; }

# A target directory of its own: the Debian route builds core from source
# with another compiler, and the host builds need not wait on it.
target_dir="$root/target/no-std"

features=$(cargo metadata --no-deps --format-version 1 --manifest-path core/Cargo.toml \
    | python3 -c '
import json, sys
meta = json.load(sys.stdin)
core = next(p for p in meta["packages"] if p["name"] == "deploywatch-core")
print(" ".join(sorted(f for f in core["features"] if f != "default")))')

echo "check-no-std: deploywatch-core for $DW_TARGET ($DW_ROUTE route); features: ${features:-none}"
failed=()
for feature in "" $features; do
    label=${feature:-"(no features)"}
    args=(--no-default-features)
    [ -n "$feature" ] && args+=(--features "$feature")
    echo "--- $label"
    # shellcheck disable=SC2086 # DW_BUILD_STD is a list of arguments
    if ! dw_cargo build --quiet -p deploywatch-core --lib --target "$DW_TARGET" \
        --target-dir "$target_dir" $DW_BUILD_STD "${args[@]}"; then
        failed+=("$label")
    fi
done

if [ ${#failed[@]} -gt 0 ]; then
    echo "check-no-std: FAILED for: ${failed[*]}" >&2
    exit 1
fi
echo "check-no-std: ok (no features and each of: ${features:-none})"
