#!/usr/bin/env bash
# The Vulkan drivers foveate is tested on, selectable without touching the system. Sourced by
# setup.sh; `select_driver NAME` exports what the Vulkan loader needs:
#   system   the system's driver (Debian bookworm: lavapipe from Mesa 22.3)
#   mesa25   lavapipe from bookworm-backports' mesa-vulkan-drivers (Mesa 25.0), downloaded once
#            and unpacked into a private directory ($FOVEATE_DRIVER_DIR, default
#            ~/.cache/foveate/drivers), never installed: installing it would also upgrade the
#            system's GL stack. Debian bookworm only (the backport links bookworm's LLVM 15).
# FOVEATE_DRIVER=NAME makes setup.sh (so demo.sh and test.sh) select it.

driver_dir() {
    echo "${FOVEATE_DRIVER_DIR:-${XDG_CACHE_HOME:-$HOME/.cache}/foveate/drivers}"
}

# Prints the ICD manifest of Mesa 25's lavapipe, fetching it first if needed. Returns 2 where it
# cannot be had (not Debian bookworm), 1 when fetching it failed.
mesa25_manifest() {
    local root manifest
    root="$(driver_dir)/mesa25"
    manifest="$root/lvp_icd.json"
    if [ -f "$manifest" ] && [ -f "$root/version" ]; then
        echo "$manifest"
        return 0
    fi
    # shellcheck disable=SC1091
    if [ "$(. /etc/os-release && echo "${VERSION_CODENAME:-}")" != bookworm ]; then
        echo "foveate drivers: mesa25 is fetched from bookworm-backports, for Debian bookworm only" >&2
        return 2
    fi
    local apt_dir="$root/apt" mirror
    # The system's Debian archive, as apt has it (a local mirror or proxy included).
    # shellcheck source=scripts/packages.sh
    . "$(dirname "${BASH_SOURCE[0]}")/packages.sh"
    mirror=$(debian_mirror) || return 1
    echo "foveate drivers: fetching Mesa 25's lavapipe from bookworm-backports ($mirror) into $root" >&2
    rm -rf "$root"
    mkdir -p "$root/deb"
    backports_apt "$apt_dir" deb update >&2 &&
        (cd "$root/deb" && backports_apt "$apt_dir" deb download mesa-vulkan-drivers/bookworm-backports) >&2 &&
        # Only lavapipe is kept: the package's other drivers are for GPUs.
        dpkg-deb -x "$root"/deb/mesa-vulkan-drivers_*.deb "$root/unpacked" || {
        echo "foveate drivers: could not fetch mesa-vulkan-drivers from bookworm-backports" >&2
        return 1
    }
    local lib
    lib=$(find "$root/unpacked" -name libvulkan_lvp.so | head -n 1)
    [ -n "$lib" ] || { echo "foveate drivers: no libvulkan_lvp.so in the package" >&2; return 1; }
    mv "$lib" "$root/libvulkan_lvp.so"
    printf '{"file_format_version": "1.0.0", "ICD": {"library_path": "%s", "api_version": "1.4.305"}}\n' \
        "$root/libvulkan_lvp.so" >"$manifest"
    dpkg-deb -f "$root"/deb/mesa-vulkan-drivers_*.deb Version >"$root/version"
    rm -rf "$apt_dir" "$root/deb" "$root/unpacked"
    echo "$manifest"
}

# select_driver NAME: exports the loader's driver selection for NAME (see above); returns 2
# where NAME cannot be had on this system, 1 on an error.
select_driver() {
    case "$1" in
        system | "")
            unset VK_ICD_FILENAMES VK_DRIVER_FILES
            ;;
        mesa25)
            local manifest
            manifest=$(mesa25_manifest) || return $?
            export VK_ICD_FILENAMES="$manifest" VK_DRIVER_FILES="$manifest"
            echo "foveate drivers: Mesa $(cat "$(dirname "$manifest")/version") lavapipe ($manifest)" >&2
            ;;
        *)
            echo "foveate drivers: unknown driver '$1' (system or mesa25)" >&2
            return 1
            ;;
    esac
}
