#!/usr/bin/env bash
# Quick start 1: set up, build, and run `foveate render` (arguments are passed through).
# Default: the lit atrium on an eye-tracked headset (Quest Pro, at half its panel per side so
# that the quick start stays quick; `--res native` for the panel), the gaze at (0.3, -0.2),
# foveated at 0.35 with the library's default foveation: its periphery at 0.6 of the screen's
# density accumulated over frames beside a 4x fovea (the cheapest configuration measured as
# accurate as aliased stereo in every motion), above
# its stereo reference (4x), both through the lens output stage, in frame.png; prints the
# plans, each run's frame and per-pass GPU times, fragments and primitives, the side-by-side
# ratios and the foveated frame's error against the reference.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/setup.sh
[ -f "$HOME/.cargo/env" ] && source "$HOME/.cargo/env"
args=("$@")
[ ${#args[@]} -gt 0 ] || args=(render --scene atrium --hmd quest-pro --res 900x960 --gaze 0.3,-0.2
    --foveate 0.35 --reference --out frame.png)
cargo run --release -q -p foveate-desktop -- "${args[@]}"
