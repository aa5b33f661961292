#!/usr/bin/env bash
# The library as crates.io would receive it: `cargo package -p foveate` (which builds the
# packaged copy on its own), then a throwaway program outside the workspace that depends on the
# unpacked package, not on this tree, and renders a frame: the crate's `headless` example,
# pasted in as a new user would. Fails if a file the build needs (a shader, say) is missing
# from the package, or if the package only builds inside the workspace.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/setup.sh
[ -f "$HOME/.cargo/env" ] && source "$HOME/.cargo/env"

echo "=== cargo package -p foveate"
cargo package -p foveate --locked --allow-dirty 2>&1 | grep -v "^\s*Compiling" || exit 1
version=$(sed -n 's/^version = "\(.*\)"/\1/p' Cargo.toml | head -n 1)
packaged="$PWD/target/package/foveate-$version"
[ -f "$packaged/shaders/scene.vert" ] || { echo "the package has no shaders" >&2; exit 1; }

program="$PWD/target/first-frame"
rm -rf "$program/src" && mkdir -p "$program/src"
cat >"$program/Cargo.toml" <<EOF
[package]
name = "first-frame"
version = "0.0.0"
edition = "2021"
publish = false

[dependencies]
foveate = { path = "$packaged" }

# Not a member of the repository's workspace: it stands alone, as a user's program would.
[workspace]
EOF
cp "$packaged/examples/headless.rs" "$program/src/main.rs"
# The package's own lock file, so the program builds with the versions the package was
# verified with.
cp "$packaged/Cargo.lock" "$program/Cargo.lock"
echo "=== a program outside the workspace, against the package, renders a frame"
frame="$program/frame.png"
rm -f "$frame"
(cd "$program" && cargo run -q --release -- "$frame")
[ -s "$frame" ] || { echo "the program wrote no frame" >&2; exit 1; }
echo "package check: the packaged crate builds alone and renders ($frame)"
