#!/usr/bin/env bash
# Adreno's own Vulkan driver and compiler (Mesa's turnip) on a machine with no Adreno, through
# Mesa's drm-shim (a preloaded library that fakes the msm kernel device): pipelines are compiled
# by Adreno's compiler (ir3) and turnip makes its own per-pass decisions; nothing executes.
# Facts: docs/adreno.md.
#
# Sourced (by adreno-check.sh) or run:
#   scripts/adreno.sh build              builds turnip and the shim once into the cache
#   scripts/adreno.sh run CHIP CMD...    runs CMD on Adreno CHIP (650 or 740, or any chip the
#                                        shim knows), e.g. scripts/adreno.sh run 650 \
#                                        target/release/foveate shaders --hmd quest-pro
#   scripts/adreno.sh beside CHIP CMD... runs CMD with turnip on CHIP beside lavapipe, which
#                                        renders and counts (compare --price-device adreno)
#   scripts/adreno.sh price CHIP ARGS... `foveate price ARGS` (built for release), beside
#
# The build: Mesa's source, pinned (MESA_VERSION below), from the Debian archive that the
# system's apt uses (bookworm-backports' source package; no host is written here), configured
# with turnip, the msm kernel interface and the drm-shim only (no LLVM), about 5 minutes on two
# cores, into $FOVEATE_DRIVER_DIR/turnip-$MESA_VERSION (default ~/.cache/foveate/drivers). The
# shim's table of chips lacks the Adreno 650 (Quest 2 and Quest Pro, Snapdragon XR2 and XR2+
# Gen 1); the build adds it, with the GMEM size Linux's msm driver gives it.
set -euo pipefail

ADRENO_MESA_VERSION=25.0.7
ADRENO_MESA_PACKAGE="mesa=25.0.7-2~bpo12+1"
ADRENO_SCRIPTS="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"

adreno_dir() {
    echo "${FOVEATE_DRIVER_DIR:-${XDG_CACHE_HOME:-$HOME/.cache}/foveate/drivers}/turnip-$ADRENO_MESA_VERSION"
}

# The Adreno 650's entry in the shim's table, after the 640's or before the 660's: chip id
# CHIPID(6, 5, 0, any) (Mesa's freedreno_devices.py knows the chip as GPU id 650) and 1 MiB + 128 KiB of GMEM,
# as Linux's drivers/gpu/drm/msm/adreno/adreno_device.c gives the A650 (`.gmem = SZ_1M +
# SZ_128K`). Fails, naming the file, where the table's shape changed.
adreno_add_650() {
    local shim=$1/src/freedreno/drm-shim/freedreno_noop.c
    grep -q '650' "$shim" && return 0
    python3 - "$shim" <<'EOF'
import re, sys
path = sys.argv[1]
text = open(path).read()
# An entry is `{ .gpu_id = 660, .chip_id = ..., .gmem_size = ..., },` or similar: copy the 660's
# shape so the build follows the table's own fields.
m = re.search(r"(\n([ \t]*)\{[^{}]*\b660\b[^{}]*\},)", text)
if not m:
    sys.exit(f"foveate adreno: no Adreno 660 entry to model the 650's on in {path}")
entry = m.group(1)
a650 = re.sub(r"\b660\b", "650", entry, count=1)
a650 = re.sub(r"CHIPID\(6, 6, 0,", "CHIPID(6, 5, 0,", a650)
if "CHIPID(6, 5, 0," not in a650:
    sys.exit(f"foveate adreno: the Adreno 660's chip id is not CHIPID(6, 6, 0, ...) in {path}")
a650 = re.sub(r"(gmem_size\s*=\s*)[^,}]+", r"\g<1>(1024 + 128) * 1024", a650)
text = text.replace(entry, a650 + entry, 1)
open(path, "w").write(text)
EOF
}

adreno_build() {
    local root src venv
    root=$(adreno_dir)
    [ -f "$root/.foveate-ready" ] && return 0
    # shellcheck source=scripts/packages.sh
    . "$ADRENO_SCRIPTS/packages.sh"
    ensure_packages bison flex libdrm-dev glslang-tools ninja-build libarchive-dev python3-venv xz-utils >&2
    local apt_dir="$root/apt" mirror
    mirror=$(debian_mirror) || return 1
    echo "foveate adreno: building turnip (Mesa $ADRENO_MESA_VERSION) into $root, from $mirror" >&2
    rm -rf "$root"
    mkdir -p "$root/src"
    backports_apt "$apt_dir" deb-src update >&2 || { echo "foveate adreno: apt-get update failed" >&2; return 1; }
    # Only the upstream tarball is needed (the Debian diff is not applied, and the archive no
    # longer held the .dsc when this was written): fetch it by name, and fail naming it.
    local tarball="mesa_$ADRENO_MESA_VERSION.orig.tar.xz"
    # apt reports the missing .dsc and Debian diff as errors: kept in a log, shown on failure.
    (cd "$root/src" && backports_apt "$apt_dir" deb-src source --download-only "$ADRENO_MESA_PACKAGE") \
        >"$root/source.log" 2>&1 || true
    if [ ! -f "$root/src/$tarball" ]; then
        cat "$root/source.log" >&2
        echo "foveate adreno: the Debian archive did not give $tarball ($ADRENO_MESA_PACKAGE in bookworm-backports, from $mirror)" >&2
        return 1
    fi
    tar -xJf "$root/src/$tarball" -C "$root/src"
    src="$root/src/mesa-$ADRENO_MESA_VERSION"
    adreno_add_650 "$src"
    # Mesa's generators run `#!/usr/bin/env python3`: the venv's python must come first on PATH
    # (a pyenv shim would otherwise answer without mako).
    venv="$root/venv"
    /usr/bin/python3 -m venv "$venv"
    "$venv/bin/pip" install -q "meson==1.12.1" mako pyyaml packaging >&2
    (
        export PATH="$venv/bin:$PATH"
        cd "$src"
        meson setup build -Dplatforms= -Dgallium-drivers= -Dvulkan-drivers=freedreno \
            -Dfreedreno-kmds=msm -Dtools=drm-shim -Dopengl=false -Degl=disabled -Dgles1=disabled \
            -Dgles2=disabled -Dglx=disabled -Dgbm=disabled -Dllvm=disabled -Dxmlconfig=disabled \
            -Dvalgrind=disabled -Dlibunwind=disabled -Dbuildtype=release -Db_ndebug=true \
            -Dvideo-codecs= --wrap-mode=nodownload >"$root/meson.log" 2>&1
        ninja -C build >"$root/ninja.log" 2>&1
    ) || { echo "foveate adreno: the build failed (see $root/meson.log, $root/ninja.log)" >&2; return 1; }
    cp "$src/build/src/freedreno/drm-shim/libfreedreno_noop_drm_shim.so" \
        "$src/build/src/freedreno/vulkan/libvulkan_freedreno.so" "$root/"
    printf '{"file_format_version": "1.0.0", "ICD": {"library_path": "%s", "api_version": "1.4.305"}}\n' \
        "$root/libvulkan_freedreno.so" >"$root/freedreno_icd.json"
    rm -rf "$apt_dir" "$root/src" "$venv"
    echo "$ADRENO_MESA_VERSION" >"$root/.foveate-ready"
    echo "foveate adreno: turnip ready in $root" >&2
}

# adreno_run CHIP CMD...: CMD with turnip on the shim's CHIP, and only CMD (the shim is preloaded
# into CMD alone, never into cargo or a shell). The shader cache is off so every pipeline is
# compiled by ir3 in this run.
adreno_run() {
    local chip=$1 root
    shift
    root=$(adreno_dir)
    [ -f "$root/.foveate-ready" ] || adreno_build
    LD_PRELOAD="$root/libfreedreno_noop_drm_shim.so" FD_GPU_ID="$chip" \
        VK_ICD_FILENAMES="$root/freedreno_icd.json" VK_DRIVER_FILES="$root/freedreno_icd.json" \
        MESA_SHADER_CACHE_DISABLE=true "$@"
}

# adreno_beside CHIP CMD...: CMD with turnip on CHIP beside the lavapipe that renders and
# counts (the system's, or the one FOVEATE_DRIVER selects: scripts/drivers.sh): the Vulkan
# loader lists both devices, so `foveate price` and `compare --price-device` use both.
adreno_beside() {
    local chip=$1 root lavapipe
    shift
    root=$(adreno_dir)
    [ -f "$root/.foveate-ready" ] || adreno_build
    # shellcheck source=scripts/drivers.sh
    . "$ADRENO_SCRIPTS/drivers.sh"
    select_driver "${FOVEATE_DRIVER:-system}"
    lavapipe=${VK_ICD_FILENAMES:-$(ls /usr/share/vulkan/icd.d/lvp_icd.*.json | head -n 1)}
    LD_PRELOAD="$root/libfreedreno_noop_drm_shim.so" FD_GPU_ID="$chip" \
        VK_ICD_FILENAMES="$root/freedreno_icd.json:$lavapipe" \
        VK_DRIVER_FILES="$root/freedreno_icd.json:$lavapipe" MESA_SHADER_CACHE_DISABLE=true "$@"
}

if [ "${BASH_SOURCE[0]}" = "$0" ]; then
    case "${1:-}" in
        build) adreno_build ;;
        run)
            [ $# -ge 3 ] || { echo "usage: scripts/adreno.sh run CHIP CMD..." >&2; exit 1; }
            shift
            adreno_run "$@"
            ;;
        beside)
            [ $# -ge 3 ] || { echo "usage: scripts/adreno.sh beside CHIP CMD..." >&2; exit 1; }
            shift
            adreno_beside "$@"
            ;;
        price)
            [ $# -ge 2 ] || { echo "usage: scripts/adreno.sh price CHIP [ARGS...]" >&2; exit 1; }
            chip=$2
            shift 2
            (cd "$ADRENO_SCRIPTS/.." && cargo build -q --release -p foveate-desktop)
            adreno_beside "$chip" "$ADRENO_SCRIPTS/../target/release/foveate" price "$@"
            ;;
        *)
            echo "usage: scripts/adreno.sh build | run CHIP CMD... | beside CHIP CMD... | price CHIP [ARGS...]" >&2
            exit 1
            ;;
    esac
fi
