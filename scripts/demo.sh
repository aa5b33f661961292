#!/usr/bin/env bash
# Quick start 1: set up, build, and run `foveate render` (arguments are passed through;
# default: the default scene at 1024² per eye, multiview, 4x MSAA, written to frame.png).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/setup.sh
[ -f "$HOME/.cargo/env" ] && source "$HOME/.cargo/env"
args=("$@")
[ ${#args[@]} -gt 0 ] || args=(render --out frame.png)
cargo run --release -q -p foveate-desktop -- "${args[@]}"
