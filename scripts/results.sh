#!/usr/bin/env bash
# Writes docs/results.md and the README's verdict table from the committed run files that
# docs/results/index.csv lists (each a CSV a command wrote, with its command, build, date and
# device): run it after adding or replacing a run. `scripts/results.sh --check` compares instead;
# the tests run that check, so a page that drifts from its runs fails CI.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/setup.sh
[ -f "$HOME/.cargo/env" ] && source "$HOME/.cargo/env"
cargo run -q --release -p foveate-desktop -- results "$@"
