#!/usr/bin/env bash
# tools/install-deps.sh off Debian: with a PATH that holds only stand-ins
# (no apt-get), it picks dnf, pacman or brew when present, and otherwise
# checks with pkg-config, exiting 0 when `make demo` can build (listing the
# optional parts that are missing) and 1 naming what is needed.
#
#   bash tests/build/test_install_deps.sh [repository root]
#
# The stand-ins: pkg-config knows the modules listed in the file $PC (a
# package manager's stand-in "installs" by writing them there); cmake, make,
# cc exist or not per case; id prints $FAKE_UID; dnf, pacman, brew, sudo
# (which then runs its command), apt-get and dpkg-query log their arguments
# to $LOG. Nothing is installed.
set -u
ROOT=$(cd "${1:-$(dirname "$0")/../..}" && pwd)
. "$ROOT/tests/cli/lib.sh" test-install-deps
BASH_BIN=$(command -v bash)
GREP_BIN=$(command -v grep)
export PC=$WORK/pc LOG=$WORK/log FAKE_UID=0

mkbin() { # folder, then the stand-ins it holds
    local d=$WORK/$1
    shift
    rm -rf "$d" && mkdir -p "$d"
    ln -s "$GREP_BIN" "$d/grep"
    printf '#!%s\necho "$FAKE_UID"\n' "$BASH_BIN" >"$d/id"
    local t
    for t in "$@"; do
        case $t in
        pkg-config)
            printf '#!%s\n[ "$1" = --exists ] || exit 2; shift\nfor m in "$@"; do grep -qx "$m" "$PC" 2>/dev/null || exit 1; done\n' \
                "$BASH_BIN" >"$d/pkg-config" ;;
        dnf | pacman | brew)
            printf '#!%s\necho "%s $*" >>"$LOG"\nprintf "yaml-0.1\\nlibpng\\nzlib\\n" >>"$PC"\n' \
                "$BASH_BIN" "$t" >"$d/$t" ;;
        sudo)
            printf '#!%s\necho "sudo $*" >>"$LOG"\nexec "$@"\n' "$BASH_BIN" >"$d/$t" ;;
        dpkg-query)
            printf '#!%s\necho "dpkg-query $*" >>"$LOG"\necho "unknown ok not-installed"\n' "$BASH_BIN" >"$d/$t" ;;
        *) printf '#!%s\necho "%s $*" >>"$LOG"\n' "$BASH_BIN" "$t" >"$d/$t" ;;
        esac
        chmod +x "$d/$t"
    done
    chmod +x "$d/id"
}
deps() { # folder: runs install-deps.sh with only that folder on PATH
    : >"$LOG"
    OUT=$(PATH=$WORK/$1 "$BASH_BIN" "$ROOT/tools/install-deps.sh" 2>&1)
    RC=$?
}
logged() { grep -qF -- "$1" "$LOG"; }

# 1. no package manager, everything make demo needs present
mkbin plain pkg-config cmake make cc
printf 'yaml-0.1\nlibpng\nzlib\n' >"$PC"
deps plain
if [ $RC = 0 ] && has "no package manager found (apt, dnf, pacman or brew); checking with pkg-config" &&
   has "optional, not found: cmocka, for make test (pkg-config cmocka)" &&
   has "optional, not found: FFmpeg's libraries" && ! has "needed, not found"; then
    ok "no package manager, the demo's libraries present: exit 0, the optional ones listed"
else
    bad "no package manager, the demo's libraries present" "rc $RC"
fi

# 2. no package manager, libpng missing
printf 'yaml-0.1\nzlib\ncmocka\n' >"$PC"
deps plain
if [ $RC = 1 ] && has "needed, not found: libpng (pkg-config libpng)" && ! has "needed, not found: zlib" &&
   ! has "cmocka, for make test"; then
    ok "no package manager, libpng missing: exit 1 naming it"
else
    bad "no package manager, libpng missing" "rc $RC"
fi

# 3. neither pkg-config nor cmake
mkbin bare cc make
deps bare
if [ $RC = 1 ] && has "needed, not found: pkg-config" && has "needed, not found: cmake" &&
   has "needed, not found: libyaml (pkg-config yaml-0.1)"; then
    ok "no pkg-config, no cmake: exit 1 naming both and the libraries"
else
    bad "no pkg-config, no cmake" "rc $RC"
fi

# 4. dnf as root, nothing installed: the demo's packages first, then the rest
mkbin fedora pkg-config cmake make cc dnf
: >"$PC"
deps fedora
if [ $RC = 0 ] && logged "dnf install -y cmake make gcc pkgconf-pkg-config libyaml-devel libpng-devel zlib-devel" &&
   logged "dnf install -y --setopt=skip_missing_names_on_install=True libcmocka-devel" &&
   has "installing with dnf"; then
    ok "dnf: installs the demo's packages, then the optional ones"
else
    bad "dnf" "rc $RC; log: $(cat "$LOG")"
fi

# 5. pacman, not root, no sudo: says so, then checks
mkbin arch pkg-config cmake make cc pacman
printf 'yaml-0.1\nlibpng\nzlib\n' >"$PC"
FAKE_UID=1000 deps arch
if [ $RC = 0 ] && has "not root and no sudo, so pacman cannot install anything" && ! logged "pacman"; then
    ok "pacman without root or sudo: nothing run, exit 0 with the libraries present"
else
    bad "pacman without root" "rc $RC"
fi

# 6. pacman with sudo as a user
mkbin arch2 pkg-config cmake make cc pacman sudo
: >"$PC"
FAKE_UID=1000 deps arch2
if [ $RC = 0 ] && logged "sudo pacman -S --needed --noconfirm cmake make gcc pkgconf libyaml libpng zlib"; then
    ok "pacman through sudo"
else
    bad "pacman through sudo" "rc $RC; log: $(cat "$LOG")"
fi

# 7. brew as a user, without sudo
mkbin mac pkg-config cmake make cc brew
: >"$PC"
FAKE_UID=501 deps mac
if [ $RC = 0 ] && logged "brew install cmake pkg-config libyaml libpng zlib" && logged "brew install cmocka"; then
    ok "brew, as a user"
else
    bad "brew" "rc $RC; log: $(cat "$LOG")"
fi

# 8. Debian (apt-get, dpkg-query) as a user without sudo: the check instead
mkbin debian pkg-config cmake make cc apt-get dpkg-query
printf 'yaml-0.1\nlibpng\nzlib\n' >"$PC"
FAKE_UID=1000 deps debian
if [ $RC = 0 ] && has "not root and no sudo, so these Debian packages cannot be installed: cmake make gcc" &&
   ! logged "apt-get"; then
    ok "apt without root or sudo: lists the packages, checks, exit 0"
else
    bad "apt without root" "rc $RC; log: $(cat "$LOG")"
fi

# 9. Debian as root: apt-get install of the missing packages, as before
FAKE_UID=0 deps debian
if [ $RC = 0 ] && logged "apt-get update -qq" &&
   logged "apt-get install -y -qq --no-install-recommends cmake make gcc pkg-config libyaml-dev libpng-dev zlib1g-dev"; then
    ok "apt as root: installs the missing Debian packages"
else
    bad "apt as root" "rc $RC; log: $(cat "$LOG")"
fi
finish
