#!/usr/bin/env bash
# CI: every pipeline foveate creates, in every technique and configuration below, compiled by
# Adreno's own driver and compiler (Mesa's turnip on the drm-shim, scripts/adreno.sh) for the
# Adreno 650 (Quest 2 and Quest Pro) and the 740 (Quest 3), with the compiler's statistics for
# each; one frame of each recorded and submitted without queries. A pipeline the driver refuses,
# a pipeline with no statistics or a frame it cannot record fails the check, naming the
# configuration. Then the negative control: a run that fails (its device lost at the first
# submission) must fail the check's own test of a run.
#
# FOVEATE_BIN: the foveate binary (default: target/debug/foveate, built if missing).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/adreno.sh
[ -f "$HOME/.cargo/env" ] && source "$HOME/.cargo/env"
bin=${FOVEATE_BIN:-target/debug/foveate}
[ -x "$bin" ] || cargo build -q -p foveate-desktop
adreno_build

# Each line: the options of one `foveate shaders` run (all stereo modes where `--stereo all`).
configs=(
    "--stereo all --msaa 4"
    "--stereo all --msaa 1 --scene atrium"
    "--stereo multiview --scene atrium --hmd quest-pro --res 256 --foveate 0.35"
    "--scene atrium --res 256 --foveate 0.35 --periphery-msaa 4"
    "--scene atrium --res 256 --foveate 0.35 --temporal-history periphery"
    "--scene atrium --res 256 --foveate 0.35 --temporal-clip variance --temporal-filter catmull-rom --temporal-neighbourhood cross --temporal-new-sample weighted"
    "--scene atrium --res 256 --foveate 0.35 --temporal-within 20"
    "--scene atrium --res 256 --foveate 0.35 --single-frame --periphery-filter catmull-rom --sharpen 0.5"
    "--scene atrium --res 256 --foveate 0.35 --single-frame --periphery-prefilter"
    "--scene atrium --res 256 --foveate 0.35 --single-frame --ring 0.6"
    "--res 256 --foveate 0.35 --single-frame --fovea-layout one-pass --no-stencil --output undistorted"
    "--res 256 --foveate 0.35 --single-frame --fovea-layout two-pass --blend-band 0.2 --tint"
    "--res 256 --hmd-mask --radial-density"
    "--res 256 --mffr far-first"
    "--res 256 --mffr near-first --far-msaa 1 --far-density 0.5"
    "--res 256 --mffr alternate-eye --split 40m"
    "--res 256 --mffr depth-shift"
    "--scene thesis --res 256 --clusters --lod --foveate 0.35 --single-frame"
    "--scene city --res 256 --foveate 0.35 --single-frame --fovea-layout one-pass"
)

failed=()
# run CHIP OPTIONS...: one configuration on one chip; its output kept in a log.
run() {
    local chip=$1 log
    shift
    log=$(mktemp)
    # shellcheck disable=SC2068 # the options split on purpose
    if FOVEATE_PIPELINE_CACHE=off adreno_run "$chip" "$bin" shaders --frames 1 $@ >"$log" 2>&1; then
        grep -h "pipelines compiled" "$log" | sed "s/^/  adreno $chip: /"
        rm -f "$log"
        return 0
    fi
    grep -v '^Unknown DRM_IOCTL' "$log" | tail -n 20 >&2
    rm -f "$log"
    return 1
}

start=$(date +%s)
for chip in 650 740; do
    for options in "${configs[@]}"; do
        # shellcheck disable=SC2086 # the options split on purpose
        run "$chip" $options || failed+=("adreno $chip: foveate shaders $options")
    done
done
# A frame that waits on its timestamps, on a device that executes nothing, is an error saying
# so (turnip waits 5 s for queries it never writes), not a hang or a bare Vulkan result.
log=$(mktemp)
if FOVEATE_PIPELINE_CACHE=off adreno_run 740 "$bin" render --res 32 --frames 1 --out "$log.png" >"$log" 2>&1 \
    || ! grep -q "the device never wrote the frame's queries" "$log"; then
    failed+=("render on a device that executes nothing: $(grep -v '^Unknown DRM_IOCTL' "$log" | tail -n 1)")
else
    echo "  render on a device that executes nothing: refused, saying why"
fi
rm -f "$log" "$log.png"
# The negative control: the check's test of a run must see a failing run fail.
if FOVEATE_LOSE_DEVICE_AFTER_SUBMITS=1 run 740 --res 64 >/dev/null 2>&1; then
    failed+=("negative control: a run whose device was lost passed the check")
else
    echo "  negative control: a run whose device is lost at its first submission fails the check, as it must"
fi
echo "adreno check: ${#configs[@]} configurations on the Adreno 650 and 740 in $(($(date +%s) - start)) s"
if [ ${#failed[@]} -gt 0 ]; then
    printf 'adreno check failed: %s\n' "${failed[@]}" >&2
    exit 1
fi
