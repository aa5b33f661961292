#!/usr/bin/env python3
"""Checks an APK of the foveate demo as Android's installer and loader would judge it.

    check_apk.py APK STUB_DIR      check the APK; STUB_DIR holds the libraries it was linked
                                   against (the NDK sysroot's for the API level, or the stubs)
    check_apk.py --self-test STUB_DIR
                                   the negative controls: libraries that must fail the checks

Checks: `aapt dump badging` shows a launchable android.app.NativeActivity, arm64-v8a native
code and the Vulkan feature; `apksigner verify` passes; the library's NEEDED entries are all
NDK platform libraries; every undefined dynamic symbol is defined, under the version it asks
for, by the NEEDED stub that defines that version (an unversioned one must be weak: looked up
at run time, absent at this API level); the library exports ANativeActivity_onCreate.
Tools: AAPT, APKSIGNER, READELF (default llvm-readelf-22) from the environment.
"""
import os
import re
import subprocess
import sys
import tempfile
import zipfile

LIBRARY = "lib/arm64-v8a/libfoveate_android.so"
# The NDK's stable platform libraries (what an app may link against).
NDK_LIBRARIES = {
    "libaaudio.so", "libamidi.so", "libandroid.so", "libbinder_ndk.so", "libc.so",
    "libcamera2ndk.so", "libdl.so", "libEGL.so", "libGLESv1_CM.so", "libGLESv2.so",
    "libGLESv3.so", "libjnigraphics.so", "liblog.so", "libm.so", "libmediandk.so",
    "libnativewindow.so", "libneuralnetworks.so", "libOpenMAXAL.so", "libOpenSLES.so",
    "libstdc++.so", "libsync.so", "libvulkan.so", "libz.so",
}


def tool(name, default):
    return os.environ.get(name, default)


def run(*cmd, input=None):
    done = subprocess.run(cmd, capture_output=True, text=True, input=input)
    if done.returncode != 0:
        raise SystemExit(f"{' '.join(cmd)} failed:\n{done.stdout}{done.stderr}")
    return done.stdout


def readelf(*args):
    return run(tool("READELF", "llvm-readelf-22"), *args)


def dynamic_symbols(path):
    """(index, name, version or None, defined, binding) for each dynamic symbol."""
    symbols = []
    for line in readelf("--dyn-syms", "--wide", path).splitlines():
        fields = line.split()
        if len(fields) < 8 or not fields[0].rstrip(":").isdigit() or fields[0] == "0:":
            continue
        name, _, version = fields[7].partition("@")
        symbols.append((int(fields[0].rstrip(":")), name, version.lstrip("@") or None,
                        fields[6] != "UND", fields[4]))
    return symbols


def versions_needed(path):
    """Dynamic symbol index → (file, version) for each symbol bound to a needed version."""
    out = readelf("-V", path)
    needs, file = {}, None
    for line in out[out.find(".gnu.version_r"):].splitlines():
        m = re.search(r"File: (\S+)", line)
        if m:
            file = m.group(1)
        m = re.search(r"Name: (\S+)\s+Flags: \S+\s+Version: (\d+)", line)
        if m:
            needs[int(m.group(2))] = (file, m.group(1))
    table = out[out.find(".gnu.version'"):out.find(".gnu.version_r")]
    by_symbol = {}
    for line in table.splitlines():
        m = re.match(r"\s*([0-9a-f]+):((\s+\d+ \(\S+\))+)", line)
        if m:
            for offset, index in enumerate(re.findall(r"(\d+) \(", m.group(2))):
                if int(index) in needs:
                    by_symbol[int(m.group(1), 16) + offset] = needs[int(index)]
    return by_symbol


def needed(path):
    return re.findall(r"\(NEEDED\)\s+Shared library: \[(.+?)\]", readelf("-d", path))


def check_library(path, stub_dir):
    """Problems with the library at path, and a summary of what it needs."""
    problems = []
    libs = needed(path)
    for lib in libs:
        if lib not in NDK_LIBRARIES:
            problems.append(f"NEEDED {lib} is not an NDK platform library")
    # Each NEEDED stub's versioned definitions, and the unversioned ones of all of them.
    defines, unversioned = {}, set()
    for lib in libs:
        stub = os.path.join(stub_dir, lib)
        if not os.path.exists(stub):
            problems.append(f"NEEDED {lib} has no stub in {stub_dir}")
            continue
        defines[lib] = set()
        for _, name, version, defined, _ in dynamic_symbols(stub):
            if defined and version:
                defines[lib].add((name, version))
            elif defined:
                unversioned.add(name)
    bound = versions_needed(path)
    counts, weak = {}, []
    exports = False
    for index, name, version, defined, binding in dynamic_symbols(path):
        if defined:
            exports |= name == "ANativeActivity_onCreate"
            continue
        if index not in bound:
            if name in unversioned:
                counts["(unversioned)"] = counts.get("(unversioned)", 0) + 1
            elif binding == "WEAK":
                weak.append(name)
            else:
                problems.append(f"{name}: undefined, unversioned and not weak")
            continue
        lib, version = bound[index]
        if (name, version) not in defines.get(lib, set()):
            problems.append(f"{name}@{version}: versioned against {lib}, which does not define it")
        else:
            key = f"{lib} {version}"
            counts[key] = counts.get(key, 0) + 1
    if not exports:
        problems.append("ANativeActivity_onCreate is not exported")
    summary = [f"NEEDED: {', '.join(libs)}"]
    summary += [f"  {n:3} undefined symbols resolve in {k}" for k, n in sorted(counts.items())]
    if weak:
        summary.append(f"  weak, looked up at run time: {', '.join(sorted(weak))}")
    summary.append("exports ANativeActivity_onCreate" if exports else "no ANativeActivity_onCreate")
    return problems, summary


def check_badging(apk):
    out = run(tool("AAPT", "aapt"), "dump", "badging", apk)
    problems = []
    wanted = {
        "a launchable android.app.NativeActivity":
            r"^launchable-activity: name='android\.app\.NativeActivity'",
        "arm64-v8a native code": r"^native-code: .*'arm64-v8a'",
        "the Vulkan 1.1 feature":
            r"^\s*uses-feature: name='android\.hardware\.vulkan\.version' version='4198400'",
    }
    for what, pattern in wanted.items():
        if not re.search(pattern, out, re.M):
            problems.append(f"aapt dump badging shows no {what}")
    keep = ("package:", "sdkVersion:", "targetSdkVersion:", "launchable-activity:",
            "native-code:", "uses-feature:", "application-label:")
    summary = [line.strip() for line in out.splitlines() if line.strip().startswith(keep)]
    return problems, summary


def check_apk(apk, stub_dir):
    problems, summary = check_badging(apk)
    verify = subprocess.run([tool("APKSIGNER", "apksigner"), "verify", "--verbose", apk],
                            capture_output=True, text=True)
    if verify.returncode != 0:
        problems.append(f"apksigner verify failed: {verify.stderr.strip() or verify.stdout.strip()}")
    else:
        summary += [l for l in verify.stdout.splitlines() if l.startswith(("Verifies", "Verified using v"))]
    with zipfile.ZipFile(apk) as z, tempfile.TemporaryDirectory() as tmp:
        if LIBRARY not in z.namelist():
            problems.append(f"the APK has no {LIBRARY}")
        else:
            path = z.extract(LIBRARY, tmp)
            lib_problems, lib_summary = check_library(path, stub_dir)
            problems += lib_problems
            summary += [f"{LIBRARY} ({os.path.getsize(path)} bytes):"] + lib_summary
    print(f"{apk} ({os.path.getsize(apk)} bytes)")
    for line in summary:
        print(f"  {line}")
    return problems


def self_test(stub_dir):
    """Libraries with one fault each must fail; one without must pass."""
    cc = tool("CC_ANDROID", "clang-22 --target=aarch64-linux-android26").split()
    cases = {
        "clean": ("void ANativeActivity_onCreate(void) {} int f(void) { extern int getpid(void); return getpid(); }", "-lc", None),
        "symbol newer than the API level": ("void ANativeActivity_onCreate(void) {} int f(void) { extern int getrandom(void); return getrandom(); }", "-lc", "undefined, unversioned and not weak"),
        "library outside the NDK": ("void ANativeActivity_onCreate(void) {}", "-lfoveate_fake", "not an NDK platform library"),
        "no entry point": ("int f(void) { return 1; }", "-lc", "ANativeActivity_onCreate is not exported"),
        "symbol under a version its library lacks": (
            "void ANativeActivity_onCreate(void) {} int f(void) { extern int getpid(void); return getpid(); }",
            "-lc_other", "versioned against libc.so, which does not define it"),
    }
    failed = False
    with tempfile.TemporaryDirectory() as tmp:
        # A library the NDK does not have, for the NEEDED case.
        fake = os.path.join(tmp, "libfoveate_fake.so")
        run(*cc, "-shared", "-nostdlib", "-fuse-ld=lld", "-o", fake, "-x", "c", "/dev/null")
        # A libc.so defining getpid under a version the real one does not have.
        script = os.path.join(tmp, "other.map")
        with open(script, "w") as f:
            f.write("LIBC_OTHER { global: getpid; };\n")
        run(*cc, "-shared", "-nostdlib", "-fuse-ld=lld", "-Wl,-soname,libc.so",
            f"-Wl,--version-script={script}", "-o", os.path.join(tmp, "libc_other.so"),
            "-x", "c", "-", input="int getpid(void) { return 0; }")
        for name, (source, lib, expected) in cases.items():
            src = os.path.join(tmp, "case.c")
            with open(src, "w") as f:
                f.write(source)
            so = os.path.join(tmp, "case.so")
            run(*cc, "-shared", "-nostdlib", "-fuse-ld=lld", f"--sysroot={stub_dir}", f"-L{stub_dir}",
                f"-L{tmp}", "-o", so, src, lib)
            problems, _ = check_library(so, stub_dir)
            ok = not problems if expected is None else any(expected in p for p in problems)
            print(f"  {'ok  ' if ok else 'FAIL'} {name}: {problems or 'no problem found'}")
            failed |= not ok
    return failed


def main():
    if len(sys.argv) == 3 and sys.argv[1] == "--self-test":
        print("check_apk self-test (each fault must be found):")
        sys.exit(1 if self_test(sys.argv[2]) else 0)
    if len(sys.argv) != 3:
        raise SystemExit(__doc__)
    problems = check_apk(sys.argv[1], sys.argv[2])
    if problems:
        print("APK check failed:\n  " + "\n  ".join(problems), file=sys.stderr)
        sys.exit(1)
    print("APK check passed")


if __name__ == "__main__":
    main()
