#!/usr/bin/env bash
# Monado, the open-source OpenXR runtime, headless (null compositor, simulated headset), for
# `foveate xr`. Debian bookworm has the OpenXR loader but no runtime, and trixie's Monado needs a
# newer glibc, so the runtime lives in a Debian trixie chroot built once with debootstrap
# (about 70 s and 850 MB) in $FOVEATE_XR_DIR (default ~/.cache/foveate/xr); nothing is
# installed on the host but debootstrap. The application runs inside the chroot too (a binary
# built on bookworm runs there). Root only (chroot). Facts: ../shared/openxr/README.md.
#   xr_root                  prints the chroot's directory, building it first if needed
#   xr_start ROOT            starts monado-service in it (background), waits for its socket
#   xr_stop                  ends the service xr_start started (by its process id)
#   xr_run ROOT CMD...       runs CMD inside the chroot, with the runtime's environment

xr_dir() {
    echo "${FOVEATE_XR_DIR:-${XDG_CACHE_HOME:-$HOME/.cache}/foveate/xr}"
}

xr_root() {
    local root
    root="$(xr_dir)/trixie"
    if [ -f "$root/.foveate-ready" ]; then
        echo "$root"
        return 0
    fi
    if [ "$(id -u)" -ne 0 ]; then
        echo "foveate xr: building the runtime's chroot needs root (debootstrap, chroot)" >&2
        return 1
    fi
    # shellcheck source=scripts/packages.sh
    . "$(dirname "${BASH_SOURCE[0]}")/packages.sh"
    ensure_packages debootstrap >&2
    local mirror
    # The system's Debian archive, as apt has it (a local mirror or proxy included).
    mirror=$(debian_mirror) || return 1
    echo "foveate xr: building a Debian trixie chroot with Monado in $root (from $mirror)" >&2
    rm -rf "$root"
    mkdir -p "$root"
    debootstrap --variant=minbase trixie "$root" "$mirror" >"$(xr_dir)/debootstrap.log" 2>&1 || {
        echo "foveate xr: debootstrap failed (see $(xr_dir)/debootstrap.log)" >&2
        return 1
    }
    chroot "$root" /usr/bin/env DEBIAN_FRONTEND=noninteractive sh -c \
        'apt-get update -qq && apt-get install -y -qq --no-install-recommends monado-service libopenxr1-monado libopenxr-loader1 mesa-vulkan-drivers vulkan-validationlayers' \
        >"$(xr_dir)/packages.log" 2>&1 || {
        echo "foveate xr: installing Monado in the chroot failed (see $(xr_dir)/packages.log)" >&2
        return 1
    }
    chroot "$root" dpkg-query -W -f='${Version}' monado-service >"$root/.foveate-ready"
    echo "$root"
}

XR_SERVICE_PID=""

xr_start() {
    local root=$1 i
    mkdir -p "$root/run/xr"
    chmod 700 "$root/run/xr"
    # A killed service leaves its socket behind, and a new one would refuse to start.
    rm -f "$root/run/xr/monado_comp_ipc"
    chroot "$root" /usr/bin/env -i PATH=/usr/sbin:/usr/bin:/sbin:/bin HOME=/root XDG_RUNTIME_DIR=/run/xr \
        XRT_COMPOSITOR_NULL=1 XRT_NO_STDIN=1 QWERTY_ENABLE=1 monado-service \
        >"$(xr_dir)/monado.log" 2>&1 &
    XR_SERVICE_PID=$!
    # Its null compositor usually starts in about 5 s on lavapipe, but twice in a row on an
    # idle 2-core machine it had not within 10 s (a start by hand just after took 5 s): wait
    # up to 60 s (a service that died ends the wait at once).
    for i in $(seq 1 600); do
        [ -S "$root/run/xr/monado_comp_ipc" ] && {
            echo "foveate xr: monado-service $(cat "$root/.foveate-ready") running (pid $XR_SERVICE_PID)" >&2
            return 0
        }
        kill -0 "$XR_SERVICE_PID" 2>/dev/null || break
        sleep 0.1
    done
    echo "foveate xr: monado-service did not start (see $(xr_dir)/monado.log)" >&2
    xr_stop
    return 1
}

xr_stop() {
    if [ -n "$XR_SERVICE_PID" ]; then
        # The service ends by the signal (status 143): not a failure of the caller's script.
        kill "$XR_SERVICE_PID" 2>/dev/null || true
        wait "$XR_SERVICE_PID" 2>/dev/null || true
        XR_SERVICE_PID=""
    fi
    return 0
}

xr_run() {
    local root=$1
    shift
    # The host's driver selection (scripts/drivers.sh) names host paths: the chroot has its own.
    chroot "$root" /usr/bin/env -u VK_ICD_FILENAMES -u VK_DRIVER_FILES -u VK_LAYER_PATH \
        XDG_RUNTIME_DIR=/run/xr "$@"
}
