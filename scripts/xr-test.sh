#!/usr/bin/env bash
# `foveate xr` against a real OpenXR runtime: Monado's simulated headset, headless (null
# compositor, lavapipe), prepared by scripts/xr-runtime.sh in a Debian trixie chroot. Each run
# has validation on and checks the first submitted frame's pixels against `foveate render`'s
# path (--check-pixels): stereo; foveated with the HMD mask from the runtime's hidden-area mesh
# (FOVEATE_XR_FRAMES frames, 300 by default); MFFR. Any failure, validation message or pixel
# difference fails the script. Root only (chroot). FOVEATE_XR_PROFILE=release times a release
# build. Logs: $FOVEATE_XR_DIR (default ~/.cache/foveate/xr), run-*.log and monado.log.
set -euo pipefail
cd "$(dirname "$0")/.."
[ -f "$HOME/.cargo/env" ] && source "$HOME/.cargo/env"
# shellcheck source=scripts/xr-runtime.sh
source scripts/xr-runtime.sh

frames=${FOVEATE_XR_FRAMES:-300}
profile=${FOVEATE_XR_PROFILE:-dev}
if [ "$profile" = release ]; then
    cargo build --release -q -p foveate-desktop
    bin=target/release/foveate
else
    cargo build -q -p foveate-desktop
    bin=target/debug/foveate
fi
root=$(xr_root)
mkdir -p "$root/opt/foveate" "$root/tmp/foveate"
cp "$bin" "$root/opt/foveate/foveate"
trap xr_stop EXIT
xr_start "$root"

status=0
run() {
    local name=$1
    shift
    local log
    log="$(xr_dir)/run-$name.log"
    echo "=== foveate xr $*"
    if xr_run "$root" FOVEATE_VALIDATION=1 RUST_LOG=foveate=info \
        /opt/foveate/foveate xr --check-pixels --save "/tmp/foveate/$name.png" "$@" >"$log" 2>&1; then
        # The application's own lines (Monado's client logs to the same streams).
        grep -E '^(runtime|  |device|workload|eyes|HMD mask|pixel check|judge|[0-9]+ frames)|foveate::xr::session\] [0-9.]+ ms/frame' "$log" |
            grep -vP '^\t' | tail -n 14
        cp "$root/tmp/foveate/$name.png" "$(xr_dir)/$name.png"
    else
        tail -n 30 "$log"
        echo "foveate xr ($name) FAILED: see $log" >&2
        status=1
    fi
}
run stereo --frames 60
run foveated-masked --frames "$frames" --foveate 0.5 --hmd-mask --judge 30
run mffr --frames 60 --mffr near-first

# A runtime that fails mid-run: once the first frame is checked and written, the service is
# stopped (SIGSTOP: it stops answering) or killed (SIGKILL: it dies). foveate must end within
# --timeout + 1 s, non-zero, with the frame written and the summary printed. Last, as the
# service is not itself afterwards (a killed one is started again for nothing else).
fault() {
    local signal=$1 log png timeout=3 app i start elapsed rc=0
    log="$(xr_dir)/run-$signal.log"
    png="$root/tmp/foveate/$signal.png"
    rm -f "$png"
    echo "=== foveate xr --timeout $timeout, the runtime sent SIG$signal after the first frame"
    timeout 120 chroot "$root" /usr/bin/env -u VK_ICD_FILENAMES -u VK_DRIVER_FILES -u VK_LAYER_PATH \
        XDG_RUNTIME_DIR=/run/xr RUST_LOG=foveate=info /opt/foveate/foveate xr --check-pixels \
        --save "/tmp/foveate/$signal.png" --timeout "$timeout" >"$log" 2>&1 &
    app=$!
    for i in $(seq 1 900); do
        [ -f "$png" ] && break
        sleep 0.1
    done
    kill "-$signal" "$XR_SERVICE_PID"
    start=$(date +%s%N)
    wait "$app" || rc=$?
    elapsed=$((($(date +%s%N) - start) / 1000000))
    [ "$signal" = STOP ] && kill -CONT "$XR_SERVICE_PID"
    grep -E 'frames rendered and submitted|^error|^wrote' "$log" | grep -vP '^\t' || true
    echo "exit $rc after $elapsed ms"
    if [ "$rc" -eq 0 ] || [ "$rc" -eq 124 ] || [ ! -f "$png" ] ||
        ! grep -q 'frames rendered and submitted' "$log" ||
        [ "$elapsed" -gt $(((timeout + 1) * 1000)) ]; then
        tail -n 30 "$log"
        echo "foveate xr (runtime sent SIG$signal) FAILED: it must end within $timeout + 1 s, non-zero, frame and summary written" >&2
        status=1
    fi
}
fault STOP
fault KILL
[ $status -eq 0 ] && echo "xr: every run submitted its frames, validation clean, pixels equal; a stalled or dead runtime ended the run in time, frame and summary kept"
exit $status
