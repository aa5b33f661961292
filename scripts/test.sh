#!/usr/bin/env bash
# Quick start 2: set up and run the whole test suite (every Vulkan test with
# VK_LAYER_KHRONOS_validation on; any validation message fails it) once per driver, then clippy
# and fmt.
#
# Drivers (scripts/drivers.sh): FOVEATE_TEST_DRIVERS="system mesa25" by default — the system's
# lavapipe, then Mesa 25's, fetched privately (Debian bookworm only: elsewhere it is skipped,
# said so). FOVEATE_DRIVER=NAME, or FOVEATE_TEST_DRIVERS=NAMES, runs only those.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/setup.sh
[ -f "$HOME/.cargo/env" ] && source "$HOME/.cargo/env"
log=$(mktemp)
trap 'rm -f "$log"' EXIT

drivers=${FOVEATE_TEST_DRIVERS:-${FOVEATE_DRIVER:-system mesa25}}
# Passed and failed tests in a `cargo test` log.
totals() {
    awk '/^test result:/ { for (i = 1; i <= NF; i++) { if ($i ~ /^passed;?$/) p += $(i-1); if ($i ~ /^failed;?$/) f += $(i-1) } }
         END { printf "%d %d\n", p, f }' "$1"
}
passed=0 failed=0 status=0 summary=()
for driver in $drivers; do
    selected=0
    select_driver "$driver" || selected=$?
    if [ "$selected" -eq 2 ] && [ -z "${FOVEATE_TEST_DRIVERS:-}${FOVEATE_DRIVER:-}" ]; then
        summary+=("$driver: skipped (not available on this system)")
        continue
    fi
    [ "$selected" -eq 0 ] || exit 1
    echo "=== the test suite on the $driver driver"
    cargo test --workspace 2>&1 | tee "$log" || status=1
    read -r p f < <(totals "$log")
    passed=$((passed + p)) failed=$((failed + f))
    summary+=("$driver: $p passed, $f failed")
done
# The library's examples (core/examples), each run as a user would run it.
echo "=== the examples"
ran=() broke=()
# Each with its arguments (the eccentricity rings at a small size: their run is the notebook's).
for run in headless own_images engine_loop judge bring_your_own_draws \
    "eflip_by_eccentricity --res 256 0.6 0.6:accumulated"; do
    read -r example args <<<"$run"
    # shellcheck disable=SC2086 # the arguments split on purpose
    if cargo run -q -p foveate --example "$example" -- $args >"$log" 2>&1; then
        ran+=("$example")
    else
        cat "$log"
        broke+=("$example")
        status=1
    fi
done
summary+=("examples: ${#ran[@]} ran (${ran[*]}), ${#broke[@]} failed${broke[*]:+ (${broke[*]})}")
printf '%s\n' "${summary[@]}"
if [ "${FOVEATE_SKIP_LINT:-0}" != "1" ]; then
    cargo fmt --all -- --check || status=1
    cargo clippy --workspace --all-targets -q -- -D warnings || status=1
    # The library as a user gets it (no `internals`): every public item documented
    # (missing_docs), and its docs built without a warning (broken links).
    cargo clippy -p foveate --features flip,clusters,xr -q -- -D warnings || status=1
    # Twice: with docs.rs's features, and with the default ones, as `cargo doc -p foveate` in a
    # user's project builds them (a link to an item behind a feature breaks only there).
    RUSTDOCFLAGS="-D warnings" cargo doc -q -p foveate --no-deps --features flip,clusters,xr \
        || status=1
    RUSTDOCFLAGS="-D warnings" cargo doc -q -p foveate --no-deps || status=1
fi
# One closing total over every driver: cargo's own last line is the (empty) doc-test run.
echo "tests: $passed passed, $failed failed"
exit $status
