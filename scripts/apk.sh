#!/usr/bin/env bash
# Builds the Android demo: a signed debug APK of foveate-android for aarch64-linux-android, in
# target/android/foveate.apk, then checks it (android/toolchain/check_apk.py).
#
# With ANDROID_NDK_HOME set: the NDK's clang and sysroot, and rustup's aarch64-linux-android
# standard library when it is installed. Without: Debian's packages only — rustc-web/cargo-web
# building std from rust-web-src (-Zbuild-std), clang-22/lld-22, and stub platform libraries
# generated from the symbol maps in android/toolchain/ndk-symbol-maps (copied from
# ../shared/android/ndk-symbol-maps; FOVEATE_NDK_SYMBOL_MAPS=DIR reads another copy).
# Either way aapt (against android-framework-res), zipalign and apksigner package and sign it.
#
#   FOVEATE_ANDROID_API=N   minimum API level (default 26: the lowest the demo supports)
#   FOVEATE_APK_PROFILE=P   cargo profile (default release)
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/setup.sh
[ -f "$HOME/.cargo/env" ] && source "$HOME/.cargo/env"

api=${FOVEATE_ANDROID_API:-26}
profile=${FOVEATE_APK_PROFILE:-release}
maps=${FOVEATE_NDK_SYMBOL_MAPS:-android/toolchain/ndk-symbol-maps}
target=aarch64-linux-android
out=$PWD/target/android
if ! [[ "$api" =~ ^[0-9]+$ ]] || [ "$api" -lt 26 ]; then
    echo "apk: FOVEATE_ANDROID_API=$api: must be a number, at least 26 (ANativeWindow, Vulkan 1.1)" >&2
    exit 2
fi
started=$SECONDS
step() { printf 'apk [%3ds] %s\n' $((SECONDS - started)) "$*"; }

ensure_packages aapt zipalign apksigner android-framework-res default-jdk-headless llvm-22 \
    python3 unzip
export READELF=llvm-readelf-22
mkdir -p "$out"

# The C compiler and the directory of platform libraries to link against.
if [ -n "${ANDROID_NDK_HOME:-}" ]; then
    ndk_bin=$(echo "$ANDROID_NDK_HOME"/toolchains/llvm/prebuilt/*/bin)
    sysroot=$(dirname "$ndk_bin")/sysroot
    if [ ! -x "$ndk_bin/clang" ] || [ ! -d "$sysroot/usr/lib/$target/$api" ]; then
        echo "apk: ANDROID_NDK_HOME=$ANDROID_NDK_HOME has no LLVM toolchain with $target API $api" >&2
        exit 2
    fi
    clang=$ndk_bin/clang
    step "NDK route: $ANDROID_NDK_HOME"
else
    ensure_packages clang-22 lld-22
    clang=clang-22
    sysroot=$out/sysroot
    libs=$sysroot/usr/lib/$target/$api
    [ -d "$maps" ] || { echo "apk: no symbol maps in $maps (FOVEATE_NDK_SYMBOL_MAPS)" >&2; exit 2; }
    step "Debian route: stub platform libraries for API $api from $maps"
    mkdir -p "$libs" "$out/stubs"
    for lib in c m dl log android; do
        python3 android/toolchain/ndk_stubs.py "$maps/lib$lib.map.txt" arm64 "$api" \
            "$out/stubs/lib$lib.s" "$out/stubs/lib$lib.map"
        $clang --target=$target$api -shared -nostdlib -fuse-ld=lld -o "$libs/lib$lib.so" \
            -Wl,--version-script="$out/stubs/lib$lib.map" -Wl,-soname,lib$lib.so "$out/stubs/lib$lib.s"
    done
    cc=($clang --target=$target$api -O2 -fPIC -ffreestanding -Wall -Werror -c)
    "${cc[@]}" -DAPI_LEVEL="$api" android/toolchain/crtbegin_so.c -o "$libs/crtbegin_so.o"
    "${cc[@]}" android/toolchain/crtend_so.c -o "$libs/crtend_so.o"
    "${cc[@]}" android/toolchain/unwind.c -o "$out/stubs/unwind.o"
    rm -f "$libs/libunwind.a"
    llvm-ar-22 rcs "$libs/libunwind.a" "$out/stubs/unwind.o"
fi
stubs=$sysroot/usr/lib/$target/$api

# The Rust toolchain: rustup's prebuilt std for the target (NDK route, when installed), else
# Debian's rustc-web building std with panic = "abort" from rust-web-src.
cargo_cmd=(cargo)
build_std=()
if [ -z "${ANDROID_NDK_HOME:-}" ] || ! rustup target list --installed 2>/dev/null | grep -qx $target; then
    ensure_packages rustc-web cargo-web rust-web-src
    cargo_cmd=(env RUSTC=/usr/bin/rustc RUSTDOC=/usr/bin/rustdoc RUSTC_BOOTSTRAP=1 /usr/bin/cargo)
    build_std=(-Zbuild-std=std,panic_abort)
fi
step "building foveate-android with $("${cargo_cmd[@]}" --version) (${build_std[*]:-prebuilt std})"
linker_args="-Clink-arg=--target=$target$api -Clink-arg=-fuse-ld=lld -Clink-arg=--sysroot=$sysroot"
CARGO_TARGET_AARCH64_LINUX_ANDROID_LINKER=$clang \
CARGO_TARGET_AARCH64_LINUX_ANDROID_RUSTFLAGS="-Cpanic=abort -Dwarnings $linker_args" \
    "${cargo_cmd[@]}" build -p foveate-android --profile "$profile" --target $target \
    "${build_std[@]}" --target-dir "$out/cargo"
# The OpenXR path (`foveate::xr`, the `xr` feature) compiles for the device too; its loader is
# C++ and needs the NDK's C++ runtime, which Debian lacks, so it is checked, not linked.
step "compile-checking foveate's OpenXR path for $target"
CARGO_TARGET_AARCH64_LINUX_ANDROID_RUSTFLAGS="-Cpanic=abort -Dwarnings" \
    "${cargo_cmd[@]}" check -q -p foveate --features xr --target $target \
    "${build_std[@]}" --target-dir "$out/cargo"
[ "$profile" = dev ] && profile_dir=debug || profile_dir=$profile
library=$out/cargo/$target/$profile_dir/libfoveate_android.so

step "packaging"
version=$(sed -n 's/^version = "\(.*\)"/\1/p' Cargo.toml | head -1)
stage=$out/stage
rm -rf "$stage" "$out/unaligned.apk" "$out/aligned.apk"
mkdir -p "$stage/lib/arm64-v8a"
cp "$library" "$stage/lib/arm64-v8a/"
sed -e "s/@VERSION@/$version/" -e "s/@API@/$api/" android/AndroidManifest.xml > "$out/AndroidManifest.xml"
aapt package -f --debug-mode -M "$out/AndroidManifest.xml" \
    -I /usr/share/android-framework-res/framework-res.apk -F "$out/unaligned.apk"
(cd "$stage" && aapt add "$out/unaligned.apk" lib/arm64-v8a/libfoveate_android.so >/dev/null)
zipalign -f -p 4 "$out/unaligned.apk" "$out/aligned.apk"

# Signed with the usual Android debug key: the developer's own when there is one.
keystore=$HOME/.android/debug.keystore
if [ ! -f "$keystore" ]; then
    keystore=$out/debug.keystore
    [ -f "$keystore" ] || keytool -genkeypair -keystore "$keystore" -storepass android \
        -alias androiddebugkey -keypass android -keyalg RSA -keysize 2048 -validity 10000 \
        -dname "CN=Android Debug,O=Android,C=US" 2>/dev/null
fi
apksigner sign --ks "$keystore" --ks-key-alias androiddebugkey --ks-pass pass:android \
    --key-pass pass:android --out "$out/foveate.apk" "$out/aligned.apk"
rm -f "$out/unaligned.apk" "$out/aligned.apk" "$out/foveate.apk.idsig"

step "checking (first the checker's negative controls, then the APK)"
CC_ANDROID="$clang --target=$target$api" python3 android/toolchain/check_apk.py --self-test "$stubs"
python3 android/toolchain/check_apk.py "$out/foveate.apk" "$stubs"
step "built target/android/foveate.apk — install with: adb install -r target/android/foveate.apk"
