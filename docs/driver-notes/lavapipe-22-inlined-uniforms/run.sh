#!/usr/bin/env bash
# Builds leak.c and one fragment shader per candidate, then runs each on a driver and prints its
# growth per frame: `run.sh [system|mesa25] [FRAMES]` (the drivers as scripts/drivers.sh names
# them; default: system, 200 frames). Needs a C compiler, libvulkan-dev and glslc.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
driver=${1:-system}
frames=${2:-200}
# shellcheck source=../../../scripts/drivers.sh
source "$here/../../../scripts/drivers.sh"
select_driver "$driver"
command -v glslc >/dev/null || { echo "run.sh: needs glslc (apt-get install glslc)" >&2; exit 1; }
[ -f /usr/include/vulkan/vulkan.h ] || { echo "run.sh: needs libvulkan-dev" >&2; exit 1; }
build=$(mktemp -d)
trap 'rm -rf "$build"' EXIT
cc -O2 -Wall -o "$build/leak" "$here/leak.c" -lvulkan
glslc -fshader-stage=vert -o "$build/leak.vert.spv" "$here/leak.vert"
# Each candidate: its name, the shader's defines, draws per frame, what is bound again before each
# draw after the first (leak.c's REBIND).
candidates=(
    "constant-loop||1|0"
    "uniform-loop|-DUNIFORM_LOOP|1|0"
    "push-constant-loop|-DPUSH_LOOP|1|0"
    "storage-loop|-DSTORAGE_LOOP|1|0"
    "uniform-if|-DUNIFORM_IF|1|0"
    "textures|-DTEXTURES|1|0"
    "uniform-loop|-DUNIFORM_LOOP|4|0"
    "uniform-loop|-DUNIFORM_LOOP|4|1"
    "uniform-loop|-DUNIFORM_LOOP|4|2"
)
cd "$build"
for c in "${candidates[@]}"; do
    IFS='|' read -r name defines draws rebind <<<"$c"
    # shellcheck disable=SC2086 # no define, or one
    glslc -fshader-stage=frag $defines -o "$name.spv" "$here/leak.frag"
    ./leak "$name.spv" "$frames" "$draws" "$rebind"
done
