#!/usr/bin/env bash
# The Python package as a newcomer installs it, with Pythons that are not
# Debian's venv: `pip install "./python[plot]"` in a fresh virtual
# environment made by uv (from PyPI, installed into a throwaway folder), and
# `pip wheel ./python`, which must give a binary wheel (cpXY-cpXY-<platform>,
# holding the compiled curray/_curray*.so) that installs into another fresh
# environment. Each environment then renders a small frame, and the [plot]
# one imports matplotlib.
#
#   tools/check-pip.sh [python ...]
#
# Pythons: those given, else the oldest and the newest pyenv CPython >= 3.9
# where pyenv is present, else a uv-managed CPython 3.9 (uv downloads it),
# else the system python3 (in a uv environment: still not Debian's venv, but
# the interpreter is Debian's, and the script says so). CURRAY_CUDA is left
# unset, so the default choice (nvcc and an NVIDIA driver) is what runs.
# Needs network access to PyPI. About 1-2 min per Python on 2 cores.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
T=$(mktemp -d "${TMPDIR:-/tmp}/curray-check-pip.XXXXXX")
trap 'rm -rf "$T"; rm -rf "$root/python/build" "$root/python/curray.egg-info"' EXIT
say() { echo "check-pip: $*"; }
fail() { echo "check-pip: FAILED: $*" >&2; exit 1; }

tool=${PYTHON_FOR_UV:-python3}
"$tool" -m venv "$T/uv" || fail "cannot make a venv for uv with $tool"
"$T/uv/bin/pip" install -q uv || fail "pip install uv (PyPI) failed"
uv=$T/uv/bin/uv
say "$("$uv" --version)"

pythons=("$@")
if [ ${#pythons[@]} = 0 ] && command -v pyenv >/dev/null; then
    mapfile -t found < <(for p in "$(pyenv root)"/versions/*/bin/python3; do
        [ -x "$p" ] && "$p" -c 'import sys; sys.exit(not (sys.implementation.name == "cpython" and sys.version_info >= (3, 9)))' 2>/dev/null &&
            echo "$("$p" -c 'import sys; print("%d.%03d" % sys.version_info[:2])') $p"
    done | sort | awk '{print $2}')
    if [ ${#found[@]} -gt 0 ]; then
        pythons=("${found[0]}")
        [ ${#found[@]} -gt 1 ] && pythons+=("${found[-1]}")
    fi
fi
if [ ${#pythons[@]} = 0 ] && "$uv" python install 3.9 >/dev/null 2>&1; then
    pythons=("$("$uv" python find 3.9)")
fi
if [ ${#pythons[@]} = 0 ]; then
    pythons=("$(command -v python3)")
    say "no pyenv and no uv-managed Python here: testing ${pythons[0]} (the system interpreter) in uv environments"
fi

smoke='
import sys, curray
img = curray.render(sys.argv[1], 24, 16)
assert img["rgb"].shape == (16, 24, 3), img["rgb"].shape
assert (img["outcome"] > 0).all()
print("render ok, backend_info", curray.backend_info())
'
n=0
for py in "${pythons[@]}"; do
    n=$((n + 1))
    ver=$("$py" -c 'import sys; print("%d.%d" % sys.version_info[:2])')
    tag=cp${ver/./}
    say "== Python $ver ($py)"
    env=$T/env$n
    "$uv" venv -q --seed -p "$py" "$env" || fail "uv venv with $py"
    t0=$SECONDS
    (cd "$root" && "$env/bin/pip" install -q "./python[plot]") ||
        fail "Python $ver: pip install ./python[plot] in a fresh environment"
    say "Python $ver: pip install ./python[plot]: $((SECONDS - t0)) s"
    (cd "$T" && "$env/bin/python" -c "$smoke" "$root/scenes/demo.yml" &&
        "$env/bin/python" -c 'import matplotlib; print("matplotlib", matplotlib.__version__)') ||
        fail "Python $ver: the installed package does not render (or no matplotlib)"

    t0=$SECONDS
    rm -rf "$T/wheels"
    (cd "$root" && "$env/bin/pip" wheel -q --no-deps -w "$T/wheels" ./python) ||
        fail "Python $ver: pip wheel ./python"
    whl=$(ls "$T"/wheels/curray-*.whl)
    say "Python $ver: pip wheel ./python: $(basename "$whl") in $((SECONDS - t0)) s"
    case $(basename "$whl") in
    *-"$tag"-"$tag"-*linux*.whl | *-"$tag"-"$tag"-*macosx*.whl) ;;
    *) fail "Python $ver: $(basename "$whl") is not a binary wheel for $tag" ;;
    esac
    # the whole listing first: grep -q would close the pipe early (pipefail)
    listing=$("$env/bin/python" -m zipfile -l "$whl") || fail "Python $ver: cannot list $whl"
    grep -q "curray/_curray.*\.so" <<<"$listing" ||
        fail "Python $ver: the wheel holds no compiled curray/_curray*.so"
    "$uv" venv -q --seed -p "$py" "$T/wenv$n"
    "$T/wenv$n/bin/pip" install -q "$whl" || fail "Python $ver: pip install of the wheel"
    (cd "$T" && "$T/wenv$n/bin/python" -c "$smoke" "$root/scenes/demo.yml") ||
        fail "Python $ver: the wheel's package does not render"
done
say "passed with ${#pythons[@]} Python(s): ${pythons[*]}"
