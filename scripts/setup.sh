#!/usr/bin/env bash
# Installs what foveate needs on Debian/Ubuntu, once: the Vulkan loader, lavapipe (CPU Vulkan),
# the Khronos validation layer, glslc and spirv-tools; for the tests, assimp's glTF test models
# (files nobody here wrote), Xvfb, xwd and xdotool (the viewer seen as a person would); checks for a
# Rust toolchain. With FOVEATE_DRIVER=mesa25, selects Mesa 25's lavapipe, fetched privately
# (scripts/drivers.sh). Idempotent and quiet when everything is already there.
set -euo pipefail

source "$(dirname "${BASH_SOURCE[0]}")/packages.sh"
source "$(dirname "${BASH_SOURCE[0]}")/drivers.sh"
ensure_packages libvulkan1 mesa-vulkan-drivers vulkan-validationlayers glslc spirv-tools \
    assimp-testmodels xvfb x11-apps xdotool

if ! command -v cargo >/dev/null 2>&1; then
    if [ -x "$HOME/.cargo/bin/cargo" ]; then
        echo "foveate setup: add ~/.cargo/bin to PATH (source ~/.cargo/env)" >&2
    else
        echo "foveate setup: installing Rust with rustup" >&2
        command -v curl >/dev/null || { echo "install curl first" >&2; exit 1; }
        curl --proto '=https' --tlsv1.2 -sSf https://sh.rustup.rs | sh -s -- -y --profile minimal
    fi
    # shellcheck disable=SC1091
    source "$HOME/.cargo/env"
fi

if [ -n "${FOVEATE_DRIVER:-}" ]; then
    select_driver "$FOVEATE_DRIVER"
fi
