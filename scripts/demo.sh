#!/usr/bin/env bash
# Quick start 1: set up, build, and run `foveate render` (arguments are passed through).
# Default: the lit atrium at 1024² per eye, foveated at 0.35 with the fovea tinted, above its
# stereo reference, both through the lens output stage, in frame.png; prints the plans, each
# run's frame and per-pass GPU times, fragments and primitives, and the side-by-side ratios.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/setup.sh
[ -f "$HOME/.cargo/env" ] && source "$HOME/.cargo/env"
args=("$@")
[ ${#args[@]} -gt 0 ] || args=(render --scene atrium --foveate 0.35 --tint --reference --out frame.png)
cargo run --release -q -p foveate-desktop -- "${args[@]}"
