#!/usr/bin/env bash
# ensure_packages PKG...: installs the Debian packages that are missing (as root or through
# sudo), quietly when all are there. Sourced by setup.sh and apk.sh.
ensure_packages() {
    local missing=() p
    for p in "$@"; do
        dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
    done
    [ ${#missing[@]} -eq 0 ] && return 0
    echo "foveate setup: installing ${missing[*]}" >&2
    local sudo=""
    [ "$(id -u)" -eq 0 ] || sudo="sudo"
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "${missing[@]}" >/dev/null
}

# debian_mirror: prints the Debian archive this system's apt takes its release from (the first
# source, one-line or deb822, whose suite is the system's codename: not the security archive,
# not a third party's), so that scripts fetching Debian packages go where apt goes (a local
# mirror or proxy included). Fails, saying so, where apt has none.
debian_mirror() {
    local codename mirror
    # shellcheck disable=SC1091
    codename=$(. /etc/os-release && echo "${VERSION_CODENAME:-}")
    mirror=$({
        awk -v c="$codename" '
            /^[[:space:]]*#/ { next }
            $1 == "deb" {
                for (i = 2; i < NF; i++) if ($i ~ /^[a-z+]+:\/\//) { if ($(i + 1) == c) print $i; break }
            }' /etc/apt/sources.list /etc/apt/sources.list.d/*.list 2>/dev/null
        awk -v c="$codename" '
            function flush() { if (uri != "" && ours) print uri; uri = ""; ours = 0 }
            FNR == 1 { flush() }
            /^[[:space:]]*#/ { next }
            /^[[:space:]]*$/ { flush(); next }
            $1 == "URIs:" { uri = $2 }
            $1 == "Suites:" { for (i = 2; i <= NF; i++) if ($i == c) ours = 1 }
            END { flush() }' /etc/apt/sources.list.d/*.sources 2>/dev/null
    } | head -n 1)
    if [ -z "$mirror" ]; then
        echo "foveate setup: no Debian archive for '$codename' in /etc/apt/sources.list or sources.list.d: add the one apt should use" >&2
        return 1
    fi
    echo "${mirror%/}"
}

# backports_apt DIR KIND ARGS...: apt-get ARGS with a private state in DIR whose one source is
# bookworm-backports (KIND: deb or deb-src) from the archive the system's apt uses
# (debian_mirror), so nothing of the system's apt changes. DIR's sources list is written the
# first time.
backports_apt() {
    local dir=$1 kind=$2 mirror
    shift 2
    if [ ! -f "$dir/sources.list" ]; then
        mirror=$(debian_mirror) || return 1
        mkdir -p "$dir/lists/partial" "$dir/cache/archives/partial"
        echo "$kind [signed-by=/usr/share/keyrings/debian-archive-keyring.gpg] $mirror bookworm-backports main" \
            >"$dir/sources.list"
    fi
    apt-get -qq -o "Dir::Etc::sourcelist=$dir/sources.list" -o Dir::Etc::sourceparts=/dev/null \
        -o "Dir::State::Lists=$dir/lists" -o "Dir::Cache=$dir/cache" \
        -o Dir::State::status=/var/lib/dpkg/status -o APT::Sandbox::User="$(id -un)" "$@"
}

