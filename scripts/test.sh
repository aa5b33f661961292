#!/usr/bin/env bash
# Quick start 2: set up and run the whole test suite (every Vulkan test with
# VK_LAYER_KHRONOS_validation on; any validation message fails it), then clippy and fmt.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/setup.sh
[ -f "$HOME/.cargo/env" ] && source "$HOME/.cargo/env"
log=$(mktemp)
trap 'rm -f "$log"' EXIT
cargo test --workspace 2>&1 | tee "$log"
# One closing total: cargo's own last line is the (empty) doc-test run.
awk '/^test result:/ { for (i = 1; i <= NF; i++) { if ($i ~ /^passed;?$/) p += $(i-1); if ($i ~ /^failed;?$/) f += $(i-1) } }
     END { printf "tests: %d passed, %d failed\n", p, f }' "$log"
if [ "${FOVEATE_SKIP_LINT:-0}" != "1" ]; then
    cargo fmt --all -- --check
    cargo clippy --workspace --all-targets -q -- -D warnings
fi
