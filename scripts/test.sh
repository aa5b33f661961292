#!/usr/bin/env bash
# Quick start 2: set up and run the whole test suite (every Vulkan test with
# VK_LAYER_KHRONOS_validation on; any validation message fails it), then clippy and fmt.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/setup.sh
[ -f "$HOME/.cargo/env" ] && source "$HOME/.cargo/env"
cargo test --workspace
if [ "${FOVEATE_SKIP_LINT:-0}" != "1" ]; then
    cargo fmt --all -- --check
    cargo clippy --workspace --all-targets -q -- -D warnings
fi
