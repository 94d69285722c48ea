#!/usr/bin/env bash
# Bad input and faults at the command line (docs/bad-input.md): every case
# runs the curray binary and checks its exit status, a substring of what it
# prints and, where output is involved, that no partial or temporary file is
# left behind.
#
#   bash tests/cli/test_cli.sh path/to/curray [repository root]
#
# Prints one line per case (ok / FAIL / skip with its reason) and a last line
# "N passed, N failed, N skipped"; exits 1 when any case failed. Runs in a
# temporary folder (curray reads config.yml in the current folder). Renders
# are tiny (8x8) but for the Ctrl-C and crash cases; the whole script takes
# about 10 s.
set -u

CURRAY=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
ROOT=$(cd "${2:-$(dirname "$0")/../..}" && pwd)
[ -x "$CURRAY" ] || { echo "test_cli: no curray binary at $CURRAY" >&2; exit 2; }

WORK=$(mktemp -d "${TMPDIR:-/tmp}/curray-test-cli.XXXXXX")
chmod 755 "$WORK"
MOUNTED=""
cleanup() {
    [ -n "$MOUNTED" ] && umount "$MOUNTED" 2>/dev/null
    chmod -R u+rwx "$WORK" 2>/dev/null
    rm -rf "$WORK"
}
trap cleanup EXIT
cd "$WORK" || exit 2

passed=0 failed=0 skipped=0
OUT=""  # what the last run printed (stdout and stderr)
RC=0    # its exit status

ok() { echo "ok   $1"; passed=$((passed + 1)); }
bad() { echo "FAIL $1: $2"; [ -n "$OUT" ] && echo "$OUT" | sed 's/^/       | /'; failed=$((failed + 1)); }
skip() { echo "skip $1: $2"; skipped=$((skipped + 1)); }

# run ARGS...: run curray (stdin not a terminal, so it never asks), with a
# time limit: a hang is a failure too. AS (an array) may hold a command that
# runs it as another user.
AS=()
run() {
    OUT=$(timeout 60 "${AS[@]}" "$CURRAY" "$@" </dev/null 2>&1)
    RC=$?
}

# Permission cases need a user that permissions apply to: root reads and
# writes anything, so as root they run curray as nobody (setpriv).
NOBODY=()
PERM_SKIP=""
if [ "$(id -u)" = 0 ]; then
    NOBODY=(setpriv --reuid=65534 --regid=65534 --clear-groups)
    if ! "${NOBODY[@]}" "$CURRAY" --version >/dev/null 2>&1; then
        PERM_SKIP="running as root, and curray cannot be run as nobody with setpriv here"
    fi
fi

# Files a failed or interrupted frame must not leave: temporaries of the
# atomic writes (".c_0.png.tmp.<pid>.<n>").
temps_in() { find "$1" -name '*.tmp.*' 2>/dev/null | head -5; }

# expect NAME RC SUBSTRING ARGS...: run curray with ARGS and check the exit
# status, the message, and that the output folder "o" was not created (every
# case here is refused before anything is written).
expect() {
    local name=$1 want_rc=$2 want_msg=$3
    shift 3
    rm -rf o
    run "$@"
    if [ "$RC" != "$want_rc" ]; then
        bad "$name" "exit status $RC, expected $want_rc"
    elif [[ "$OUT" != *"$want_msg"* ]]; then
        bad "$name" "message lacks '$want_msg'"
    elif [ -e o ]; then
        bad "$name" "the output folder was created for a refused run"
    else
        ok "$name"
    fi
}

# scene NAME RC SUBSTRING YAML [curray options...]: write YAML to bad.yml and
# render it into o at 8x8.
scene() {
    local name=$1 want_rc=$2 want_msg=$3 yaml=$4
    shift 4
    printf '%s' "$yaml" >bad.yml
    expect "$name" "$want_rc" "$want_msg" -s bad.yml -o o -x 8 -y 8 -a true "$@"
}

GOOD=$'metric: {m: 1, a: 0, q: 0}\nobserver: {r: 20, theta: 90, phi: 0, hfov: 60}\n'
OBS=$'observer: {r: 20, theta: 90, phi: 0, hfov: 60}\n'
MET=$'metric: {m: 1, a: 0, q: 0}\n'
printf '%s' "$GOOD" >good.yml
mkdir adir
touch afile

# --- a good run, as a reference --------------------------------------------
rm -rf o
run -s good.yml -o o -x 8 -y 8 -t icrd -a true
if [ "$RC" = 0 ] && [ -f o/c_0.png ] && [ -f o/r_0.png ] && [ -f o/d_0.csv ] && [ -f o/info.txt ] &&
    [ -z "$(temps_in o)" ]; then ok "good scene renders"; else bad "good scene renders" "rc $RC"; fi
# the log goes to <output>/log/, never to log/ in the current folder
if [ "$RC" = 0 ] && grep -q 'frame 0 of 1 done' o/log/curray.log && [ ! -e log ]; then
    ok "log in the output folder (o/log/curray.log)"
else
    bad "log in the output folder (o/log/curray.log)" "rc $RC; $(ls -d log o/log 2>&1 | tr '\n' ' ')"
fi
# redshift_sky: true colours the sky of r_0.png (the colour image is unchanged);
# the colours themselves are checked in test_output
rm -rf o2
printf '%sredshift_sky: true\n' "$GOOD" >skyshift.yml
run -s skyshift.yml -o o2 -x 8 -y 8 -t icr -a true
if [ "$RC" = 0 ] && cmp -s o/c_0.png o2/c_0.png && ! cmp -s o/r_0.png o2/r_0.png &&
    grep -q 'sky in redshift image  coloured by its shift' o2/info.txt; then
    ok "redshift_sky colours the sky in r_0.png only"
else
    bad "redshift_sky colours the sky in r_0.png only" "rc $RC"
fi
# -t s needs a Keplerian disc: refused before rendering, nothing written;
# with one it writes s_0.csv (its values: test_spectrum)
expect "-t s without a Keplerian disc" 1 \
    "curray: -t s: the spectrum is that of a Keplerian disc, and the scene has no disc" \
    -s good.yml -o o -x 8 -y 8 -t is -a true
printf '%s' "$GOOD" >kep.yml
printf 'accretion: {model: keplerian, radius: [12]}\nspectrum: {line: {bins: 4}}\n' >>kep.yml
rm -rf o
run -s kep.yml -o o -x 16 -y 16 -t s -a true
if [ "$RC" = 0 ] && [ -f o/s_0.csv ] && [ "$(head -1 o/s_0.csv)" = "spectrum,bin,e_lo_kev,e_hi_kev,e_kev,g,flux,normalised" ] &&
    [ "$(grep -c '^line,' o/s_0.csv)" = 4 ] && [[ "$OUT" == *"-t s: only "*" rays meet the inner disc"* ]]; then
    ok "-t s writes s_0.csv and warns about a coarse image"
else
    bad "-t s writes s_0.csv" "rc $RC"
fi
rm -rf o2

# --- missing or unreadable files -------------------------------------------
expect "missing scene file" 1 "scene file nope.yml: cannot open: No such file or directory" \
    -s nope.yml -o o -x 8 -y 8
expect "scene file is a folder" 1 "adir: read error: Is a directory" -s adir -o o -x 8 -y 8
expect "missing configuration" 1 "configuration file nope.yml: cannot open: No such file" \
    -s good.yml -c nope.yml -o o -x 8 -y 8
expect "configuration is a folder" 1 "configuration file adir: read error: Is a directory" \
    -s good.yml -c adir -o o -x 8 -y 8
if [ -z "$PERM_SKIP" ]; then
    cp good.yml noread.yml && chmod 000 noread.yml
    cp "$ROOT/scenes/sky_grid.png" noread.png && chmod 000 noread.png
    AS=("${NOBODY[@]}")
    expect "unreadable scene (no permission)" 1 "scene file noread.yml: cannot open: Permission denied" \
        -s noread.yml -o o -x 8 -y 8
    expect "unreadable configuration (no permission)" 1 "configuration file noread.yml: cannot open: Permission denied" \
        -s good.yml -c noread.yml -o o -x 8 -y 8
    scene "unreadable sky image (no permission)" 1 "cannot read PNG 'noread.png': Permission denied" \
        "$GOOD"$'skymap: {image: noread.png, boundary: 50}\n'
    AS=()
else
    skip "unreadable scene (no permission)" "$PERM_SKIP"
    skip "unreadable configuration (no permission)" "$PERM_SKIP"
    skip "unreadable sky image (no permission)" "$PERM_SKIP"
fi
printf 'cpu: {threads: 4\n' >config.yml
expect "broken config.yml in the current folder" 1 \
    "configuration file config.yml:2:1: YAML syntax error" -s good.yml -o o -x 8 -y 8
rm config.yml
scene "missing sky image" 1 "skymap.image: cannot read PNG 'nope.png': No such file or directory" \
    "$GOOD"$'skymap: {image: nope.png, boundary: 50}\n'
printf 'not an image\n' >text.png
scene "sky image is not a PNG" 1 "cannot read PNG 'text.png': not a PNG file (wrong signature)" \
    "$GOOD"$'skymap: {image: text.png, boundary: 50}\n'
: >empty.png
scene "sky image is empty" 1 "not a PNG file (wrong signature, the file is empty)" \
    "$GOOD"$'skymap: {image: empty.png, boundary: 50}\n'
head -c 200 "$ROOT/scenes/sky.png" >trunc.png
scene "sky image is truncated" 1 "cannot read PNG 'trunc.png': the file is truncated" \
    "$GOOD"$'skymap: {image: trunc.png, boundary: 50}\n'
# A PNG signature and a valid IHDR chunk (CRC included) claiming
# 100000 x 100000 pixels, and nothing else.
printf '\x89PNG\r\n\x1a\n\x00\x00\x00\x0dIHDR\x00\x01\x86\xa0\x00\x01\x86\xa0\x08\x02\x00\x00\x00\x27\x30\x9c\x9f' >huge.png
scene "sky image header claims 100000x100000" 1 \
    "the image is 100000 x 100000 = 10000000000 pixels (30000000000 bytes as 8-bit RGB), more than the limit" \
    "$GOOD"$'skymap: {image: huge.png, boundary: 50}\n'
scene "sky image path is a folder" 1 "cannot read PNG 'adir': Is a directory" \
    "$GOOD"$'skymap: {image: adir, boundary: 50}\n'

# --- malformed YAML ---------------------------------------------------------
scene "unclosed flow mapping" 1 "bad.yml:2:9: YAML syntax error: did not find expected ',' or '}' (while parsing a flow mapping at line 1, column 9)" \
    $'metric: {m: 1, a: 0, q: 0\n'"$OBS"
scene "tab indentation" 1 "bad.yml:2:1: YAML syntax error: found character that cannot start any token" \
    $'metric:\n\tm: 1\n'
scene "bad indentation" 1 "bad.yml:3:5: YAML syntax error: mapping values are not allowed in this context" \
    $'metric:\n  m: 1\n   a: 0\n'
expect "a PNG given as the scene" 1 "sky.png:1:1: YAML syntax error: invalid leading UTF-8 octet" \
    -s "$ROOT/scenes/sky.png" -o o -x 8 -y 8
scene "empty scene file" 1 "the scene file is empty" ""
scene "two YAML documents" 1 "bad.yml:4:1: a second YAML document starts here" "$GOOD"$'---\nx: 1\n'
scene "scene is a list" 1 "a scene must be a mapping of keys" $'- 1\n- 2\n'
# libyaml's scanner is quadratic in the nesting depth: 1 MB of '[' would run
# for hours without the depth limit (the time limit of run() catches a hang).
scene "lists nested a million deep" 1 "bad.yml:3:75: lists and mappings nested more than 64 levels deep" \
    "$GOOD"'sky_color: '"$(head -c 1000000 /dev/zero | tr '\0' '[')"

# --- wrong types ------------------------------------------------------------
scene "word where a number belongs" 1 'bad.yml:2:15: observer.r: expected a number, got "abc"' \
    "$MET"$'observer: {r: abc, theta: 90, phi: 0, hfov: 60}\n'
scene "number with a unit" 1 'observer.r: expected a plain number without a unit, got "20 deg"' \
    "$MET"$'observer: {r: 20 deg, theta: 90, phi: 0, hfov: 60}\n'
scene "unknown angle unit" 1 "observer.theta: unknown angle unit 'grad'" \
    "$MET"$'observer: {r: 20, theta: 90 grad, phi: 0, hfov: 60}\n'
scene "colour list too short" 1 "bad.yml:3:12: sky_color: expected a colour [R, G, B], got a list of 2 items" \
    "$GOOD"$'sky_color: [0, 0]\n'
scene "colour list too long" 1 "sky_color: expected a colour [R, G, B], got a list of 4 items" \
    "$GOOD"$'sky_color: [0, 0, 0, 0]\n'
scene "colour component 256" 1 'bad.yml:3:16: sky_color[1]: expected a colour component, an integer from 0 to 255, got "256"' \
    "$GOOD"$'sky_color: [0, 256, 0]\n'
scene "colour component -1" 1 'sky_color[0]: expected a colour component, an integer from 0 to 255, got "-1"' \
    "$GOOD"$'sky_color: [-1, 0, 0]\n'
scene "colour component 1.5" 1 'horizon_color[2]: expected a colour component, an integer from 0 to 255, got "1.5"' \
    "$GOOD"$'horizon_color: [0, 0, 1.5]\n'
scene "number where a list belongs" 1 'accretion.resolution: expected a resolution [radial divisions, sectors], got "5"' \
    "$GOOD"$'accretion: {color1: [0, 255, 0], resolution: 5, radius: [6, 15]}\n'
scene "mapping where a number belongs" 1 "bad.yml:1:13: metric.m: expected a number, got a mapping" \
    $'metric: {m: {x: 1}, a: 0, q: 0}\n'"$OBS"
scene "unknown animation" 1 "unknown animation \"cubic\"" \
    "$MET"$'observer: {r: 20, theta: 90, phi: [cubic, 0, 1], hfov: 60}\n'

# --- unknown, missing and duplicate keys ------------------------------------
scene "unknown key" 1 "bad.yml:2:48: unknown key 'colour' in observer (expected one of: r, theta, phi" \
    "$MET"$'observer: {r: 20, theta: 90, phi: 0, hfov: 60, colour: 1}\n'
scene "unknown top-level key" 1 "bad.yml:3:1: unknown key 'sphere2' at the top level" \
    "$GOOD"$'sphere2: {}\n'
scene "missing required key" 1 "observer: missing required key 'hfov'" \
    "$MET"$'observer: {r: 20, theta: 90, phi: 0}\n'
scene "missing observer" 1 "missing required key 'observer'" "$MET"
scene "duplicate key" 1 "duplicate key 'r' (first given at line 2" \
    "$MET"$'observer: {r: 20, r: 30, theta: 90, phi: 0, hfov: 60}\n'
printf 'cpu: {threads: 4}\nlog: {verbos: true}\n' >c.yml
expect "unknown configuration key" 1 "c.yml:2:7: unknown key 'verbos' in log" \
    -s good.yml -c c.yml -o o -x 8 -y 8
expect "--backend with an unknown name" 2 "--backend: expected auto, cpu or cuda, got 'gpu'" \
    -s good.yml -o o -x 8 -y 8 --backend gpu
# a value glued to -v/-q/-a is that option's value, refused when it is not
# true or false (it used to be stepped back over and re-read forever)
expect "glued value -q-a" 2 "-q: expected true or false, got '-a'" -s good.yml -o o -x 8 -y 8 -q-a
expect "glued value -v-1" 2 "-v: expected true or false, got '-1'" -s good.yml -o o -x 8 -y 8 -v-1
expect "glued value -a-q" 2 "-a: expected true or false, got '-q'" -s good.yml -o o -x 8 -y 8 -a-q
expect "glued value --verbose=-x" 2 "-v: expected true or false, got '-x'" \
    -s good.yml -o o -x 8 -y 8 --verbose=-x
expect "--threads above the limit" 2 "--threads: expected a number of threads from 1 to 4096, got '4097'" \
    -s good.yml -o o -x 8 -y 8 --threads 4097
printf 'cpu: {threads: 4097}\n' >c.yml
expect "configuration: threads above the limit" 1 'cpu.threads: expected a number of threads from 1 to 4096, got "4097"' \
    -s good.yml -c c.yml -o o -x 8 -y 8
printf 'cpu: {simd: fast}\n' >c.yml
expect "configuration: cpu.simd neither auto nor off" 1 'c.yml:1:13: cpu.simd: unknown simd "fast" (expected one of: auto, off)' \
    -s good.yml -c c.yml -o o -x 8 -y 8
# cpu.simd: off renders on the scalar path and says so (-v, info.txt); a CPU
# without AVX2 (CURRAY_TEST_CPU_FEATURES=none takes it away) gets it too
printf 'cpu: {simd: off}\n' >c.yml
rm -rf o
run -s good.yml -c c.yml -o o -x 8 -y 8 -a true -v true -t i
if [ "$RC" = 0 ] && [[ "$OUT" == *"backend cpu ("*", scalar)"* ]] &&
    grep -q "backend.*, scalar)" o/info.txt && grep -q "SIMD  *off" o/info.txt; then
    ok "cpu.simd: off renders on the scalar path"
else
    bad "cpu.simd: off renders on the scalar path" "exit status $RC or no 'scalar' in -v / info.txt"
fi
rm -rf o
OUT=$(CURRAY_TEST_CPU_FEATURES=none timeout 60 "$CURRAY" -s good.yml -o o -x 8 -y 8 -a true -v true -t i </dev/null 2>&1)
RC=$?
if [ "$RC" = 0 ] && [[ "$OUT" == *"backend cpu ("*", scalar)"* ]]; then
    ok "a CPU without AVX2 gets the scalar path"
else
    bad "a CPU without AVX2 gets the scalar path" "exit status $RC or no 'scalar' in -v"
fi
rm -rf o
printf 'cpu: {threads: many}\n' >c.yml
expect "configuration: word for a number" 1 'c.yml:1:16: cpu.threads: expected a number of threads from 1 to 4096, got "many"' \
    -s good.yml -c c.yml -o o -x 8 -y 8

# --- non-finite numbers -----------------------------------------------------
scene "NaN" 1 'observer.r: expected a finite number, got ".nan"' \
    "$MET"$'observer: {r: .nan, theta: 90, phi: 0, hfov: 60}\n'
scene "infinity" 1 'metric.m: expected a finite number, got ".inf"' $'metric: {m: .inf, a: 0, q: 0}\n'"$OBS"
scene "overflowing number" 1 'observer.r: expected a finite number, got "1e999"' \
    "$MET"$'observer: {r: 1e999, theta: 90, phi: 0, hfov: 60}\n'
scene "infinite angle" 1 'observer.theta: expected a finite angle, got "-inf deg"' \
    "$MET"$'observer: {r: 20, theta: -inf deg, phi: 0, hfov: 60}\n'
scene "overflowing angle" 1 'observer.phi: expected a finite angle, got "1e308 pi"' \
    "$MET"$'observer: {r: 20, theta: 90, phi: 1e308 pi, hfov: 60}\n'
printf 'raytracer: {step_multiplier: .inf}\n' >c.yml
expect "configuration: infinity" 1 'raytracer.step_multiplier: expected a finite number, got ".inf"' \
    -s good.yml -c c.yml -o o -x 8 -y 8

# --- physically impossible scenes (ERRATA item 4) ---------------------------
scene "no horizon (a > M)" 1 "a^2 + q^2 = 4 exceeds m^2 = 1, so there is no event horizon" \
    $'metric: {m: 1, a: 2, q: 0}\n'"$OBS"
scene "no horizon (a^2 + Q^2 > M^2)" 1 "so there is no event horizon" $'metric: {m: 1, a: 0.8, q: 0.7}\n'"$OBS"
scene "zero mass" 1 "metric.m = 0: the mass M must be positive" $'metric: {m: 0, a: 0, q: 0}\n'"$OBS"
scene "negative mass" 1 "metric.m = -1: the mass M must be positive" $'metric: {m: -1, a: 0, q: 0}\n'"$OBS"
scene "observer inside the horizon" 1 "observer.r = 1.5 is inside the event horizon r+ = 2, where no observer can stay at rest" \
    "$MET"$'observer: {r: 1.5, theta: 90, phi: 0, hfov: 60}\n'
scene "observer on the horizon" 1 "observer.r = 2 is on the event horizon r+ = 2" \
    "$MET"$'observer: {r: 2, theta: 90, phi: 0, hfov: 60}\n'
scene "observer inside the ergosphere" 1 "is inside the ergosphere (r_E+ = 2): no static observer exists there" \
    $'metric: {m: 1, a: 0.9, q: 0}\nobserver: {r: 1.9, theta: 90, phi: 0, hfov: 60}\n'
scene "observer theta outside 0..180" 1 "observer.theta = 200 deg lies outside 0 to 180 deg" \
    "$MET"$'observer: {r: 20, theta: 200, phi: 0, hfov: 60}\n'
scene "observer too far out for doubles" 1 "observer.r = 1e+160 with metric.m = 1 is out of the range" \
    "$MET"$'observer: {r: 1e160, theta: 90, phi: 0, hfov: 60}\n'
scene "observer beyond 1e75 M" 1 "observer.r = 1e+100: an observer at a finite r may be at most 1e+75 M from the hole (the integration's powers of r overflow beyond about 1e77 M, and every pixel would be an error ray); for a distant observer use r: inf with hextent" \
    "$MET"$'observer: {r: 1e100, theta: 90, phi: 0, hfov: 60}\n'
scene "observer beyond 1e75 M, in units of M" 1 "observer.r = 3e+75 (1.5e+75 M with metric.m = 2): an observer at a finite r may be at most 1e+75 M" \
    $'metric: {m: 2, a: 0, q: 0}\nobserver: {r: 3e75, theta: 90, phi: 0, hfov: 60}\n'
scene "hfov 180" 1 "observer.hfov = 180 deg: a field of view must lie between 0 and 180 deg" \
    "$MET"$'observer: {r: 20, theta: 90, phi: 0, hfov: 180}\n'
scene "hfov 0" 1 "observer.hfov = 0 deg: a field of view must lie between 0 and 180 deg" \
    "$MET"$'observer: {r: 20, theta: 90, phi: 0, hfov: 0}\n'
scene "vfov negative" 1 "observer.vfov = -10 deg: a field of view must lie between 0 and 180" \
    "$MET"$'observer: {r: 20, theta: 90, phi: 0, hfov: 60, vfov: -10}\n'
scene "disc r_in >= r_out" 1 "accretion.radius: the inner radius 15 must be below the outer radius 6" \
    "$GOOD"$'accretion: {color1: [0, 255, 0], resolution: [2, 12], radius: [15, 6]}\n'
scene "disc r_in = r_out" 1 "the inner radius 6 must be below the outer radius 6" \
    "$GOOD"$'accretion: {color1: [0, 255, 0], resolution: [2, 12], radius: [6, 6]}\n'
scene "disc r_in negative" 1 "accretion.radius: the inner radius -1 is negative" \
    "$GOOD"$'accretion: {color1: [0, 255, 0], resolution: [2, 12], radius: [-1, 6]}\n'
scene "disc resolution 0" 1 'accretion.resolution[0]: expected a positive integer, got "0"' \
    "$GOOD"$'accretion: {color1: [0, 255, 0], resolution: [0, 12], radius: [6, 15]}\n'
scene "keplerian unknown model" 1 'accretion.model: unknown disc model "kepler" (expected one of: chessboard, keplerian)' \
    "$GOOD"$'accretion: {model: kepler, radius: [6, 15]}\n'
scene "keplerian temperature 0" 1 "accretion.temperature: the peak temperature must be positive (kelvin), got 0" \
    "$GOOD"$'accretion: {model: keplerian, radius: [6, 15], temperature: 0}\n'
scene "keplerian r_in inside horizon" 1 "accretion.radius: the inner radius 1.5 is at or inside the event horizon r+ = 2" \
    "$GOOD"$'accretion: {model: keplerian, radius: [1.5, 15]}\n'
scene "keplerian retrograde ISCO beyond r_out" 1 "accretion.radius: the retrograde ISCO r_isco = 8.71735 lies at or beyond the outer radius 8" \
    $'metric: {m: 1, a: 0.9, q: 0}\nobserver: {r: 20, theta: 90, phi: 0, hfov: 60}\naccretion: {model: keplerian, radius: [3, 8], retrograde: true}\n'
scene "keplerian near-extremal spin" 1 "too close to an extremal hole for the keplerian disc" \
    $'metric: {m: 1, a: 0.999999, q: 0}\nobserver: {r: 20, theta: 90, phi: 0, hfov: 60}\naccretion: {model: keplerian, radius: [20]}\n'
# the key at fault, not the spin (a = 0 is far from extremal)
scene "keplerian outer radius too large" 1 "accretion.radius: the outer radius 1e+300 of the keplerian disc may be at most 1e+15 M (the disc's flux table cannot resolve the flux peak over a longer span" \
    "$GOOD"$'accretion: {model: keplerian, radius: [6, 1e300]}\n'
scene "keplerian outer radius too large, in units of M" 1 "accretion.radius: the outer radius 4e+15 (in units of metric.m) of the keplerian disc may be at most 1e+15 M" \
    $'metric: {m: 2, a: 0, q: 0}\nobserver: {r: 40, theta: 90, phi: 0, hfov: 60}\naccretion: {model: keplerian, radius: [4e15]}\n'
scene "keplerian mass_msun too large" 1 "bad.yml:3:59: accretion.mass_msun: the hole's mass must lie between 1e-100 and 1e+100 solar masses (the temperature is computed from it in SI units, in doubles), got 1e+300" \
    "$GOOD"$'accretion: {model: keplerian, radius: [6, 20], mass_msun: 1e300, mdot_edd: 1e-300}\n'
scene "keplerian mdot_edd too small" 1 "bad.yml:3:73: accretion.mdot_edd: the accretion rate must lie between 1e-100 and 1e+100 Eddington units" \
    "$GOOD"$'accretion: {model: keplerian, radius: [6, 20], mass_msun: 10, mdot_edd: 1e-300}\n'
scene "keplerian temperature too high" 1 "accretion.temperature: the peak temperature must lie between 0 and 1e+300 kelvin (the disc's temperature scale overflows above that), got 1.7e+308" \
    "$GOOD"$'accretion: {model: keplerian, radius: [6, 20], temperature: 1.7e308}\n'
for case in "radius: [1e15], temperature: 1e300" "radius: [1e15], temperature: 1e-300" "radius: [6, 20], mass_msun: 1e100, mdot_edd: 1e-100" "radius: [20], mass_msun: 1e-100, mdot_edd: 1e100"; do
    printf '%saccretion: {model: keplerian, %s}\n' "$GOOD" "$case" >edge.yml
    rm -rf o
    run -s edge.yml -o o -x 8 -y 8 -t c -a true
    if [ "$RC" = 0 ] && [ -s o/c_0.png ]; then ok "keplerian at its limits renders ($case)"; else bad "keplerian at its limits ($case)" "rc $RC"; fi
done
scene "keplerian exposure 0" 1 "bad.yml:3:58: accretion.exposure: the exposure must lie above 0 and at most 1e+100 (a factor on the disc's light; 1 is the default, 2 twice as bright), got 0" \
    "$GOOD"$'accretion: {model: keplerian, radius: [6, 20], exposure: 0}\n'
scene "keplerian exposure animated to a negative value" 1 "accretion.exposure: the exposure must lie above 0 and at most 1e+100 (a factor on the disc's light; 1 is the default, 2 twice as bright), got -1" \
    "$GOOD"$'accretion: {model: keplerian, radius: [6, 20], exposure: [linear, 1, -1]}\n'
scene "keplerian exposure a word" 1 "bad.yml:3:58: accretion.exposure: expected auto or a positive number (the factor on the disc's light), got \"bright\"" \
    "$GOOD"$'accretion: {model: keplerian, radius: [6, 20], exposure: bright}\n'
scene "chessboard exposure" 1 "accretion.exposure: applies only to model: keplerian" \
    "$GOOD"$'accretion: {color1: [0, 255, 0], resolution: [2, 12], radius: [6, 15], exposure: 2}\n'
scene "keplerian mdot_edd 0" 1 "accretion.mdot_edd: the accretion rate must be positive (Eddington units), got 0" \
    "$GOOD"$'accretion: {model: keplerian, radius: [15], mass_msun: 10, mdot_edd: 0}\n'
scene "keplerian mass_msun negative" 1 "accretion.mass_msun: the hole's mass must be positive (solar masses), got -10" \
    "$GOOD"$'accretion: {model: keplerian, radius: [15], mass_msun: -10, mdot_edd: 0.1}\n'
scene "keplerian temperature and mass" 1 "accretion.mass_msun: give either accretion.temperature (the peak temperature) or accretion.mass_msun with accretion.mdot_edd (the physical inputs), not both" \
    "$GOOD"$'accretion: {model: keplerian, radius: [15], temperature: 5000, mass_msun: 10, mdot_edd: 0.1}\n'
scene "keplerian mdot without mass" 1 "accretion.mdot_edd: accretion.mass_msun and accretion.mdot_edd go together" \
    "$GOOD"$'accretion: {model: keplerian, radius: [15], mdot_edd: 0.1}\n'
scene "keplerian inside_isco unknown" 1 'accretion.inside_isco: unknown value "gas" (expected one of: nothing, plunging)' \
    "$GOOD"$'accretion: {model: keplerian, radius: [15], inside_isco: gas}\n'
scene "keplerian plunging outside the ISCO" 1 "accretion.inside_isco = plunging: the matter falls from the prograde ISCO r_isco = 6, but the inner radius 8 lies outside it" \
    "$GOOD"$'accretion: {model: keplerian, radius: [8, 15], inside_isco: plunging}\n'
scene "chessboard inside_isco" 1 "accretion.inside_isco: applies only to model: keplerian" \
    "$GOOD"$'accretion: {color1: [0, 255, 0], resolution: [2, 12], radius: [6, 15], inside_isco: plunging}\n'
scene "sphere radius 0" 1 "radius = 0 must be positive" \
    "$GOOD"$'sphere: {color: [0, 0, 255], resolution: [4, 8], r: 8, theta: 90, phi: 0, radius: 0}\n'
scene "sky boundary 0" 1 "skymap.boundary = 0 must be positive" \
    "$GOOD"$'skymap: {image: '"$ROOT"$'/scenes/sky_grid.png, boundary: 0}\n'
scene "impossible only in the last frame" 1 "bad.yml: frame 2 of 3: metric.a = 2, metric.q = 0: a^2 + q^2 = 4 exceeds m^2 = 1" \
    $'metric: {m: 1, a: [linear, 0, 2], q: 0}\n'"$OBS" -f 3

# --- integrator, tolerance, the observer and the sky at infinity ------------
printf 'raytracer: {integrator: euler}\n' >c.yml
expect "unknown integrator" 1 'c.yml:1:25: raytracer.integrator: unknown integrator "euler" (expected one of: mino, rk4)' \
    -s good.yml -c c.yml -o o -x 8 -y 8
printf 'raytracer: {tolerance: 0}\n' >c.yml
expect "tolerance 0" 1 'c.yml:1:24: raytracer.tolerance: expected a positive number, got "0"' \
    -s good.yml -c c.yml -o o -x 8 -y 8
printf 'raytracer: {tolerance: -1e-8}\n' >c.yml
expect "negative tolerance" 1 'c.yml:1:24: raytracer.tolerance: expected a positive number, got "-1e-8"' \
    -s good.yml -c c.yml -o o -x 8 -y 8
printf 'raytracer: {tolerance: tight}\n' >c.yml
expect "tolerance is a word" 1 'c.yml:1:24: raytracer.tolerance: expected a number, got "tight"' \
    -s good.yml -c c.yml -o o -x 8 -y 8
printf 'raytracer: {tolerance: .nan}\n' >c.yml
expect "tolerance NaN" 1 'c.yml:1:24: raytracer.tolerance: expected a finite number, got ".nan"' \
    -s good.yml -c c.yml -o o -x 8 -y 8
printf 'raytracer: {samples: 0}\n' >c.yml
expect "samples 0" 1 'c.yml:1:22: raytracer.samples: expected an integer from 1 to 16, got "0"' \
    -s good.yml -c c.yml -o o -x 8 -y 8
printf 'raytracer: {samples: -1}\n' >c.yml
expect "negative samples" 1 'c.yml:1:22: raytracer.samples: expected an integer from 1 to 16, got "-1"' \
    -s good.yml -c c.yml -o o -x 8 -y 8
printf 'raytracer: {samples: 2.5}\n' >c.yml
expect "fractional samples" 1 'c.yml:1:22: raytracer.samples: expected an integer from 1 to 16, got "2.5"' \
    -s good.yml -c c.yml -o o -x 8 -y 8
printf 'raytracer: {samples: abc}\n' >c.yml
expect "samples is a word" 1 'c.yml:1:22: raytracer.samples: expected an integer from 1 to 16, got "abc"' \
    -s good.yml -c c.yml -o o -x 8 -y 8
printf 'raytracer: {samples: 17}\n' >c.yml
expect "too many samples" 1 'c.yml:1:22: raytracer.samples: expected an integer from 1 to 16, got "17"' \
    -s good.yml -c c.yml -o o -x 8 -y 8
printf 'raytracer: {samples: 2}\n' >c.yml
rm -rf o
run -s good.yml -c c.yml -o o -x 8 -y 8 -t ci -a true
if [ "$RC" = 0 ] && [ -s o/c_0.png ] && grep -q '^  samples  *2 x 2 per pixel$' o/info.txt; then
    ok "samples 2 renders, info.txt shows it"
else
    bad "samples 2 renders, info.txt shows it" "exit status $RC"
fi
rm -rf o
INF=$'observer: {r: inf, theta: 85, phi: 0, hextent: 40}\n'
scene "r: inf, no horizon (a > M)" 1 "metric.a = 1.2, metric.q = 0: a^2 + q^2 = 1.44 exceeds m^2 = 1, so there is no event horizon" \
    $'metric: {m: 1, a: 1.2, q: 0}\n'"$INF"
scene "r: inf, no horizon (Q > M)" 1 "metric.a = 0, metric.q = 1.5: a^2 + q^2 = 2.25 exceeds m^2 = 1" \
    $'metric: {m: 1, a: 0, q: 1.5}\n'"$INF"
scene "r: inf, image plane width 0" 1 "observer.hextent = 0: the width of the image plane must be positive" \
    "$MET"$'observer: {r: inf, theta: 85, phi: 0, hextent: 0}\n'
scene "r: inf, negative image plane width" 1 "observer.hextent = -10: the width of the image plane must be positive" \
    "$MET"$'observer: {r: inf, theta: 85, phi: 0, hextent: -10}\n'
scene "r: inf, image plane height 0" 1 "observer.vextent = 0: the height of the image plane must be positive" \
    "$MET"$'observer: {r: inf, theta: 85, phi: 0, hextent: 40, vextent: 0}\n'
scene "r: inf, an image plane too wide (every ray an error)" 1 "observer.hextent = 1e+160: the image plane at infinity may be at most 1e+150 M wide (the squared impact parameter of a wider one overflows, and every pixel would be an error ray)" \
    "$MET"$'observer: {r: inf, theta: 85, phi: 0, hextent: 1e160}\n'
scene "r: inf, just over the widest image plane" 1 "observer.hextent = 1.0000001e+150: the image plane at infinity may be at most 1e+150 M wide" \
    "$MET"$'observer: {r: inf, theta: 85, phi: 0, hextent: 1.0000001e150}\n'
scene "r: inf, too high an image plane from the aspect ratio" 1 "observer.vextent = 8e+150 (hextent x height / width): the image plane at infinity may be at most 1e+150 M high (the squared impact parameter of a wider one overflows, and every pixel would be an error ray); use a smaller hextent or a wider image" \
    "$MET"$'observer: {r: inf, theta: 85, phi: 0, hextent: 1e150}\n' -x 1
scene "r: inf, too high an image plane in units of M" 1 "observer.vextent = 3e+150 (1.5e+150 M with metric.m = 2): the image plane at infinity may be at most 1e+150 M high" \
    $'metric: {m: 2, a: 0, q: 0}\nobserver: {r: inf, theta: 85, phi: 0, hextent: 40, vextent: 3e150}\n'
# the widest image plane and the farthest observer trace every ray
for case in "r: inf, theta: 85, phi: 0, hextent: 1e150, vextent: 1e150" "r: 1e75, theta: 60, phi: 0, hfov: 60"; do
    printf 'metric: {m: 1, a: 0.998, q: 0.05}\nobserver: {%s}\n' "$case" >edge.yml
    rm -rf o
    run -s edge.yml -o o -x 8 -y 8 -t ic -a true
    if [ "$RC" = 0 ] && grep -q '^  pixels  *horizon 0, disc 0, sphere 0, sky 64, error 0, limit 0$' o/info.txt &&
        [[ "$OUT" != *warning* ]]; then
        ok "at the limit, every ray traced ($case)"
    else
        bad "at the limit, every ray traced ($case)" "rc $RC: $(grep pixels o/info.txt 2>/dev/null)"
    fi
done
# rays that end in error are counted in a warning, on the console and in
# info.txt (rk4 from r = 1e60 M overflows in every ray)
printf 'raytracer: {integrator: rk4}\n' >rk4.yml
printf 'metric: {m: 1, a: 0.9, q: 0}\nobserver: {r: 1e60, theta: 85, phi: 0, hfov: 60}\n' >far.yml
rm -rf o
run -s far.yml -c rk4.yml -o o -x 8 -y 8 -t ic -a true
want="64 of 64 rays ended in error (the integration met a number that is not finite) and are painted in error_color (blue by default)"
if [ "$RC" = 0 ] && [[ "$OUT" == *"curray: warning: frame 0: $want"* ]] &&
    grep -q "^  warning  *$want" o/info.txt; then
    ok "error rays are counted in a warning (console and info.txt)"
else
    bad "error rays are counted in a warning" "rc $RC: $(grep warning o/info.txt 2>/dev/null)"
fi
scene "r: inf without hextent" 1 "bad.yml:2:1: observer: missing required key 'hextent'" \
    "$MET"$'observer: {r: inf, theta: 85, phi: 0}\n'
scene "r: inf with hfov" 1 "bad.yml:2:39: observer.hfov: an observer at infinity (r: inf) has no field of view; give the width of its image plane with hextent" \
    "$MET"$'observer: {r: inf, theta: 85, phi: 0, hfov: 60}\n'
scene "hextent with a finite r" 1 "bad.yml:2:48: observer.hextent: applies only to the observer at infinity (r: inf)" \
    "$MET"$'observer: {r: 20, theta: 90, phi: 0, hfov: 60, hextent: 40}\n'
scene "r: inf with pitch" 1 "bad.yml:2:59: observer.pitch: must be 0: an observer at infinity (r: inf) always looks at the hole and can only roll" \
    "$MET"$'observer: {r: inf, theta: 85, phi: 0, hextent: 40, pitch: 10}\n'
scene "r: inf animated" 1 "bad.yml:2:24: observer.r[1]: inf (the observer at infinity) cannot be animated" \
    "$MET"$'observer: {r: [linear, inf, 30], theta: 85, phi: 0, hextent: 40}\n'
scene "r: -inf" 1 'bad.yml:2:15: observer.r: expected a positive number or inf (the observer at infinity), got "-inf"' \
    "$MET"$'observer: {r: -inf, theta: 85, phi: 0, hextent: 40}\n'
printf 'raytracer: {integrator: rk4}\n' >c.yml
printf '%s' "$MET$INF" >inf.yml
expect "r: inf with the rk4 integrator" 1 "raytracer.integrator = rk4: the rk4 integrator cannot start at infinity (observer.r: inf); use mino" \
    -s inf.yml -c c.yml -o o -x 8 -y 8
# the good case: an observer at infinity, its sky at infinity (no boundary)
rm -rf o
printf '%s' "$MET$INF" >inf_good.yml
printf 'skymap: {image: %s}\n' "$ROOT/scenes/sky_grid.png" >>inf_good.yml
run -s inf_good.yml -o o -x 8 -y 8 -t icd -a true
if [ "$RC" = 0 ] && [ -f o/c_0.png ] && [ -f o/d_0.csv ] &&
    grep -q '^  r  *inf (the observer at infinity)$' o/info.txt &&
    grep -q '^  image plane width  *40 M$' o/info.txt &&
    grep -q '^  boundary R  *inf (the sky at infinity)$' o/info.txt &&
    grep -q '^  integrator  *mino$' o/info.txt; then
    ok "observer and sky at infinity render"
else
    bad "observer and sky at infinity render" "exit status $RC"
fi
rm -rf o
scene "sky boundary -inf" 1 'skymap.boundary: expected a positive number or inf (the sky at infinity), got "-inf"' \
    "$GOOD"$'skymap: {image: '"$ROOT"$'/scenes/sky_grid.png, boundary: -inf}\n'
scene "sky boundary animated to inf" 1 "skymap.boundary[2]: inf (the sky at infinity) cannot be animated" \
    "$GOOD"$'skymap: {image: '"$ROOT"$'/scenes/sky_grid.png, boundary: [linear, 50, inf]}\n'

# --- the flat screen's field of view; rays on the limits; an observer just
# outside the horizon --------------------------------
scene "hfov 179: the flat screen cannot show it" 1 "observer.hfov = 179 deg: the flat screen cannot show more than 170 deg" \
    "$MET"$'observer: {r: 20, theta: 90, phi: 0, hfov: 179}\n'
# --- moving observers and projections ----------------------------
KERR=$'metric: {m: 1, a: 0.9, q: 0}\n'
scene "motion: speed of light" 1 "observer.motion = [0.6, 0, 0.8]: the speed |v| = 1 must be below 1" \
    "$KERR"$'observer: {r: 20, theta: 90, phi: 0, hfov: 60, motion: [0.6, 0, 0.8]}\n'
scene "motion: speed reaches 1 in the last frame" 1 "frame 2 of 3: observer.motion = [0, 0, 1.1]" \
    "$KERR"$'observer: {r: 20, theta: 90, phi: 0, hfov: 60, motion: [0, 0, [linear, 0, 1.1]]}\n' -f 3
scene "motion: orbit inside the photon orbit" 1 "observer.motion = orbit: no timelike circular orbit exists at observer.r = 1.5" \
    "$KERR"$'observer: {r: 1.5, theta: 90, phi: 0, hfov: 60, motion: orbit}\n'
scene "motion: orbit off the equator" 1 "observer.motion = orbit: circular orbits lie in the equatorial plane" \
    "$KERR"$'observer: {r: 10, theta: 60, phi: 0, hfov: 60, motion: orbit}\n'
scene "motion: static inside the ergosphere" 1 "observer.r = 1.8 at theta = 90 deg is inside the ergosphere" \
    "$KERR"$'observer: {r: 1.8, theta: 90, phi: 0, hfov: 60, motion: static}\n'
scene "motion: unknown" 1 "observer.motion: unknown motion" \
    "$KERR"$'observer: {r: 10, theta: 90, phi: 0, hfov: 60, motion: hover}\n'
scene "projection: unknown" 1 "observer.projection: unknown projection \"cubemap\" (expected one of: rectilinear, fisheye, equirectangular)" \
    "$KERR"$'observer: {r: 10, theta: 90, phi: 0, hfov: 60, projection: cubemap}\n'
scene "projection: fisheye over 360 deg" 1 "observer.hfov = 400 deg: a fisheye's field of view must lie above 0 and at most 360 deg" \
    "$KERR"$'observer: {r: 10, theta: 90, phi: 0, hfov: 400, projection: fisheye}\n'
# a value just past a limit is printed with the digits that show it is past
# (with %g: "hfov = 360 deg ... at most 360", "|v| = 1 must be below 1")
scene "fisheye just over 360 deg: enough digits" 1 "observer.hfov = 360.0000001 deg: a fisheye's field of view must lie above 0 and at most 360 deg" \
    "$KERR"$'observer: {r: 10, theta: 90, phi: 0, hfov: 360.0000001, projection: fisheye}\n'
scene "hfov just over 170 deg: enough digits" 1 "observer.hfov = 170.0000001 deg: the flat screen cannot show more than 170 deg" \
    "$KERR"$'observer: {r: 10, theta: 90, phi: 0, hfov: 170.0000001}\n'
scene "speed just over 1: enough digits" 1 "observer.motion = [0.6, 0.8, 1e-05]: the speed |v| = 1.0000000001 must be below 1" \
    "$KERR"$'observer: {r: 20, theta: 90, phi: 0, hfov: 60, motion: [0.6, 0.8, 0.00001]}\n'
scene "motion at infinity" 1 "observer.motion: the observer at infinity (r: inf) is static" \
    "$KERR"$'observer: {r: inf, theta: 90, phi: 0, hextent: 30, motion: infall}\n'
scene "motion: sideways on the polar axis" 1 "observer.motion = [0, 0.1, 0]: on the polar axis (theta = 0 deg) e_theta and e_phi are not defined" \
    "$KERR"$'observer: {r: 10, theta: 0, phi: 0, hfov: 60, motion: [0, 0.1, 0]}\n'
# a folder named info.txt in the output folder: refused before rendering,
# naming it (was "cannot rename ...: Is a directory" after the first frame,
# and "Input/output error" with --resume)
rm -rf fi && mkdir -p fi/info.txt
for extra in "" --resume; do
    run -s good.yml -o fi -x 8 -y 8 -t ic -a true $extra
    if [ "$RC" = 1 ] && [[ "$OUT" == *"fi/info.txt is a folder, where this run writes its summary info.txt; move it away, or choose another output folder with -o"* ]] &&
       [ ! -e fi/c_0.png ] && [ -z "$(temps_in fi)" ]; then
        ok "a folder named info.txt ${extra:+($extra) }is refused, naming it"
    else
        bad "a folder named info.txt ${extra:+($extra)}" "exit status $RC"
    fi
done
rm -rf fi
# rays that end on max_steps: own colour (yellow), a warning, a line in info.txt
rm -rf o
printf 'raytracer: {integrator: rk4, max_steps: 50}\n' >limits.yml
run -s good.yml -o o -x 8 -y 8 -t icd -a true -c limits.yml
if [ "$RC" = 0 ] && [[ "$OUT" == *"warning: frame 0: 64 rays ended on raytracer.max_steps"* ]] &&
    grep -q '^  warning  *64 rays: ended on raytracer.max_steps' o/info.txt &&
    [ "$(grep -c ',255,255,0,50,' o/d_0.csv)" = 64 ]; then
    ok "limit rays: yellow, warned on the console and in info.txt"
else
    bad "limit rays: yellow, warned on the console and in info.txt" "rc $RC; $(grep -c ',255,255,0,' o/d_0.csv 2>&1)"
fi
# listing 7.1.5 from r = 2.004, closer to r+ = 2 than 2 x horizon_epsilon: rays
# stop halfway instead, and it says so (before: every ray was horizon at step 0)
rm -rf o
printf '%s' "$MET"$'observer: {r: 2.004, theta: 85, phi: 0, yaw: 180, hfov: 70}\n' >near.yml
run -s near.yml -o o -x 16 -y 16 -t id -a true
sky=$(awk -F, '$10 == "sky"' o/d_0.csv 2>/dev/null | wc -l)
if [ "$RC" = 0 ] && [[ "$OUT" == *"closer to the horizon than 2 x raytracer.horizon_epsilon"* ]] &&
    [ "$sky" -gt 0 ]; then
    ok "observer at r+ + 0.004 sees the sky ($sky of 256 pixels), with a warning"
else
    bad "observer at r+ + 0.004 sees the sky, with a warning" "rc $RC, $sky sky pixels"
fi

# --- sizes and frame counts -------------------------------------------------
expect "width 0" 2 "-x: expected a width from 1 to 65536 pixels, got '0'" -s good.yml -o o -x 0 -y 8
expect "negative height" 2 "-y: expected a height from 1 to 65536 pixels, got '-5'" -s good.yml -o o -x 8 -y -5
expect "width is a word" 2 "-x: expected a width from 1 to 65536 pixels, got 'wide'" -s good.yml -o o -x wide -y 8
expect "width 100000" 2 "got '100000'" -s good.yml -o o -x 100000 -y 8
expect "65536x65536 frame" 2 "more than the 268435456 this version renders (it would need about 192.0 GiB of memory)" \
    -s good.yml -o o -x 65536 -y 65536
expect "no frame size" 2 "the frame size is required" -s good.yml -o o -x 8
expect "zero frames" 2 "-f: expected a frame count from 1 to 1000000, got '0'" -s good.yml -o o -x 8 -y 8 -f 0
expect "negative frames" 2 "-f: expected a frame count from 1 to 1000000, got '-3'" -s good.yml -o o -x 8 -y 8 -f -3
expect "absurd frame count" 2 "-f: expected a frame count from 1 to 1000000, got '99999999999'" \
    -s good.yml -o o -x 8 -y 8 -f 99999999999
expect "unknown output type" 2 "-t: unknown output type 'z'" -s good.yml -o o -x 8 -y 8 -t cz
# More memory than the process may use: refused before the frame buffers (or
# the scene) are allocated. Sanitizer builds reserve terabytes of address
# space and cannot start under ulimit -v at all.
if (ulimit -v 3000000 && "$CURRAY" --version) >/dev/null 2>&1; then
    rm -rf o
    OUT=$( (ulimit -v 3000000 && exec timeout 60 "$CURRAY" -s good.yml -o o -x 16384 -y 16384 -a true) 2>&1)
    RC=$?
    if [ "$RC" = 1 ] && [[ "$OUT" == *"a 16384x16384 frame (1 frame) needs about 18."*" GiB of memory, more than the 2.86 GiB of the address-space limit"* ]] &&
        [ ! -e o ]; then
        ok "frame larger than the memory limit"
    else
        bad "frame larger than the memory limit" "exit status $RC"
    fi
else
    skip "frame larger than the memory limit" "curray cannot start under ulimit -v (a sanitizer build)"
fi
# The memory check counts what else a run holds: each worker's FITS file
# (built in memory, 65 bytes a pixel) and the thread stacks. Under
# ulimit -v 600000 a 2300x2300 -t icf run fits without its FITS file
# (0.4 GiB) but not with it (0.72 GiB): it used to render and then fail in
# cfitsio. 64 threads of 8 MiB stacks (0.52 GiB) do not fit 300000 KiB.
if (ulimit -v 3000000 && "$CURRAY" --version) >/dev/null 2>&1; then
    rm -rf o
    OUT=$( (ulimit -v 600000 && exec timeout 120 "$CURRAY" -s good.yml -o o -x 2300 -y 2300 -t icf -a true) 2>&1)
    RC=$?
    if [[ "$OUT" == *"built without cfitsio"* ]]; then
        skip "FITS counted by the memory check" "this build has no cfitsio"
    elif [ "$RC" = 1 ] && [[ "$OUT" == *"a 2300x2300 frame (1 frame) needs about 0.7"*" GiB of memory, more than the 0.57 GiB of the address-space limit"* ]] &&
        [ ! -e o ]; then
        ok "FITS counted by the memory check: refused before rendering"
    else
        bad "FITS counted by the memory check" "exit status $RC"
    fi
    OUT=$( (ulimit -v 300000 && ulimit -s 8192 && exec timeout 60 "$CURRAY" -s good.yml -o o -x 8 -y 8 --threads 64 -a true) 2>&1)
    RC=$?
    if [ "$RC" = 1 ] && [[ "$OUT" == *"a 8x8 frame (1 frame) needs about 0.5"*" GiB of memory, more than the 0.29 GiB of the address-space limit"* ]] &&
        [ ! -e o ]; then
        ok "thread stacks counted by the memory check (64 threads)"
    else
        bad "thread stacks counted by the memory check" "exit status $RC"
    fi
else
    skip "FITS and thread stacks counted by the memory check" "curray cannot start under ulimit -v (a sanitizer build)"
fi
# A sky image that decodes to far more than its file (a decompression bomb:
# 16384 x 16384 black pixels, 805 MB, from a file of about 800 KB) is refused
# before it is decoded, naming it (it was accepted without a word).
if command -v python3 >/dev/null; then
    python3 - bomb.png <<'PY'
import struct, sys, zlib
w = h = 16384
def chunk(t, d):
    return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xffffffff)
z = zlib.compressobj(9)
row = bytes(1 + 3 * w)
data = b"".join(z.compress(row) for _ in range(h)) + z.flush()
with open(sys.argv[1], "wb") as f:
    f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)) +
            chunk(b"IDAT", data) + chunk(b"IEND", b""))
PY
    scene "sky image: a decompression bomb" 1 \
        "skymap.image: cannot read PNG 'bomb.png': its " \
        "$GOOD"$'skymap: {image: bomb.png, boundary: 50}\n'
    [[ "$OUT" == *"bytes decode to 16384 x 16384 pixels, 805306368 bytes, "*" times as many (a decompression bomb"* ]] ||
        bad "decompression bomb message" "$OUT"
    rm -f bomb.png
else
    bad "sky image: a decompression bomb" "no python3 to write the PNG"
fi

# --- output folder ----------------------------------------------------------
expect "output folder under a regular file" 1 "cannot create folder 'afile/out': 'afile' exists and is not a folder" \
    -s good.yml -o afile/out -x 8 -y 8
expect "output folder is a regular file" 1 "cannot create folder 'afile': it exists and is not a folder" \
    -s good.yml -o afile -x 8 -y 8
if [ -z "$PERM_SKIP" ]; then
    mkdir -p ro && chmod 555 ro
    AS=("${NOBODY[@]}")
    run -s good.yml -o ro -x 8 -y 8 -t icrd -a true
    if [ "$RC" = 1 ] && [[ "$OUT" == *"cannot write 'ro/c_0.png': cannot create a file in its folder: Permission denied"* ]] &&
        [ -z "$(ls -A ro)" ]; then ok "read-only output folder"; else bad "read-only output folder" "exit status $RC"; fi
    run -s good.yml -o ro/sub -x 8 -y 8 -a true
    if [ "$RC" = 1 ] && [[ "$OUT" == *"cannot create folder 'ro/sub': cannot create 'ro/sub': Permission denied"* ]] &&
        [ -z "$(ls -A ro)" ]; then ok "output folder in a read-only folder"; else bad "output folder in a read-only folder" "exit status $RC"; fi
    AS=()
    chmod 755 ro
else
    skip "read-only output folder" "$PERM_SKIP"
    skip "output folder in a read-only folder" "$PERM_SKIP"
fi
rm -rf o2
mkdir o2
touch o2/log
run -s good.yml -o o2 -x 8 -y 8 -a true
if [ "$RC" = 0 ] && [[ "$OUT" == *"warning: cannot create the log file o2/log/curray.log"*"(logging to the console only)"* ]] &&
    [ -f o2/c_0.png ]; then ok "log folder cannot be created (warning only)"; else bad "log folder cannot be created (warning only)" "exit status $RC"; fi
rm -rf o2

# A full disk: a 96 KiB file system holds frame 0 (info.txt, c_, r_, the log and a
# 50 KB d_0.csv) but not frame 1. Frame 1 must leave no file of its own and
# no temporary; info.txt must list frame 0 only.
mkdir full
if [ "$(id -u)" = 0 ] && mount -t tmpfs -o size=96k tmpfs full 2>/dev/null; then
    MOUNTED=$WORK/full
    run -s good.yml -o full/out -x 24 -y 24 -f 3 -t icrd -a true
    why=""
    [ "$RC" = 1 ] || why="exit status $RC, expected 1"
    [[ "$OUT" == *"No space left on device"* ]] || why=${why:-"message lacks 'No space left on device'"}
    [[ "$OUT" == *"1 of 3 frames were finished and kept in full/out"* ]] || why=${why:-"message lacks '1 of 3 frames were finished'"}
    for f in c_0.png r_0.png d_0.csv info.txt; do [ -s "full/out/$f" ] || why=${why:-"frame 0 lost $f"}; done
    for f in c_1.png r_1.png d_1.csv c_2.png r_2.png d_2.csv; do [ -e "full/out/$f" ] && why=${why:-"the failed frame left $f"}; done
    [ -z "$(temps_in full)" ] || why=${why:-"temporary files left: $(temps_in full)"}
    grep -q '^Frame 0$' full/out/info.txt && ! grep -q '^Frame [12]$' full/out/info.txt &&
        grep -q 'Finished 1 of 3 frames (run incomplete)' full/out/info.txt || why=${why:-"info.txt does not list frame 0 alone"}
    if [ -z "$why" ]; then ok "full disk"; else bad "full disk" "$why"; fi
    # the same with no room even for frame 0: nothing is left but the log folder
    rm -rf full/out
    head -c 60000 /dev/zero >full/filler 2>/dev/null
    run -s good.yml -o full/out -x 24 -y 24 -t icrd -a true
    if [ "$RC" = 1 ] && [[ "$OUT" == *"No space left on device"* ]] && [ -z "$(ls -A full/out | grep -v '^log$')" ]; then
        ok "full disk at the first frame"
    else
        bad "full disk at the first frame" "exit status $RC; left: $(ls -A full/out | tr '\n' ' ')"
    fi
    umount full && MOUNTED=""
else
    skip "full disk" "needs root and 'mount -t tmpfs' (not permitted here)"
    skip "full disk at the first frame" "needs root and 'mount -t tmpfs' (not permitted here)"
fi

# --- console output closed early ---------------------------------------------
# curray ... | head -c 1: the reader goes away before the render starts; the
# render must finish anyway (no death by SIGPIPE half-way through a file).
rm -rf pp
timeout 60 "$CURRAY" -s good.yml -o pp -x 8 -y 8 -f 3 -t icrd -a true </dev/null 2>/dev/null | head -c 1 >/dev/null
RC=${PIPESTATUS[0]}
OUT=""
if [ "$RC" = 0 ] && [ -s pp/c_2.png ] && [ -s pp/d_2.csv ] && grep -q 'Finished 3 of 3 frames$' pp/info.txt &&
    [ -z "$(temps_in pp)" ]; then ok "console output closed early (| head -c 1)"; else bad "console output closed early (| head -c 1)" "exit status $RC"; fi

# --- Ctrl-C -----------------------------------------------------------------
# SIGINT once frame 0 is written: exit status 130; the finished frames are
# kept whole, the frame in progress leaves no file and no temporary, and
# info.txt lists exactly the finished frames.
rm -rf si
"$CURRAY" -s "$ROOT/scenes/demo.yml" -o si -x 32 -y 32 -f 200 -t icrd --threads 1 -a true </dev/null >si.log 2>&1 &
pid=$!
for _ in $(seq 600); do [ -f si/info.txt ] && break; sleep 0.1; done
sleep 0.2
kill -INT "$pid" 2>/dev/null
for _ in $(seq 300); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
if kill -0 "$pid" 2>/dev/null; then
    kill -KILL "$pid"
    wait "$pid" 2>/dev/null
    OUT=$(cat si.log)
    bad "Ctrl-C during a render" "still running 30 s after SIGINT"
else
    wait "$pid"
    RC=$?
    OUT=$(cat si.log)
    n_c=$(ls si | grep -c '^c_')
    why=""
    [ "$RC" = 130 ] || why="exit status $RC, expected 130"
    [[ "$OUT" == *"interrupted; $n_c of 200 frames finished and kept in si"* ]] || why=${why:-"message lacks 'interrupted; $n_c of 200 frames finished'"}
    [[ "$OUT" == *"kept in si; the same command with --resume renders the rest"* ]] || why=${why:-"message does not point to --resume"}
    [ "$n_c" -ge 1 ] && [ "$n_c" -lt 200 ] || why=${why:-"$n_c frames kept"}
    for ((k = 0; k < n_c; k++)); do
        for f in c_$k.png r_$k.png d_$k.csv; do [ -s "si/$f" ] || why=${why:-"finished frame lacks $f"}; done
        grep -q "^Frame $k\$" si/info.txt || why=${why:-"info.txt lacks frame $k"}
    done
    for f in "c_$n_c.png" "r_$n_c.png" "d_$n_c.csv"; do [ -e "si/$f" ] && why=${why:-"the interrupted frame left $f"}; done
    [ "$(grep -c '^Frame ' si/info.txt)" = "$n_c" ] || why=${why:-"info.txt lists other frames"}
    grep -q "Finished $n_c of 200 frames (run incomplete)" si/info.txt || why=${why:-"info.txt lacks 'Finished $n_c of 200'"}
    [ -z "$(temps_in si)" ] || why=${why:-"temporary files left: $(temps_in si)"}
    if [ -z "$why" ]; then ok "Ctrl-C during a render (frames kept: $n_c)"; else bad "Ctrl-C during a render" "$why"; fi
fi

# --- frames count from 0; the console and info.txt show what is in use ------
printf 'cpu: {threads: 2}\n' >c.yml
rm -rf fr
run -s good.yml -c c.yml -o fr -x 8 -y 8 -f 2 --threads 3 -a true
why=""
[ "$RC" = 0 ] || why="exit status $RC"
[[ "$OUT" == *"frame 0 of 2 done"* && "$OUT" == *"frame 1 of 2 done"* ]] || why=${why:-"console lacks 'frame 0 of 2 done' and 'frame 1 of 2 done'"}
[[ "$OUT" == *"frame 2 of 2"* ]] && why=${why:-"console counts frames from 1"}
grep -Eq 'CPU threads +3$' fr/info.txt || why=${why:-"info.txt does not show --threads 3: $(grep 'CPU threads' fr/info.txt)"}
if [ -z "$why" ]; then ok "frames count from 0; info.txt shows --threads"; else bad "frames count from 0; info.txt shows --threads" "$why"; fi

# --- the prompt on a terminal (script(1) gives curray a pseudo-terminal) -----
if command -v script >/dev/null 2>&1; then
    for answer in " y" "" "Y" "  yes"; do
        rm -rf pr
        OUT=$(printf '%s\n' "$answer" | timeout 60 script -qec "'$CURRAY' -s good.yml -o pr -x 8 -y 8" /dev/null 2>&1)
        RC=$?
        if [ "$RC" = 0 ] && [[ "$OUT" == *"Proceed with rendering? [Y/n]"* ]] && [ -f pr/c_0.png ]; then
            ok "prompt answered '$answer' renders"
        else
            bad "prompt answered '$answer' renders" "exit status $RC"
        fi
    done
    for answer in " n" "no"; do
        rm -rf pr
        OUT=$(printf '%s\n' "$answer" | timeout 60 script -qec "'$CURRAY' -s good.yml -o pr -x 8 -y 8" /dev/null 2>&1)
        RC=$?
        if [ "$RC" = 0 ] && [[ "$OUT" == *"not rendering (declined)"* ]] && [ ! -e pr ]; then
            ok "prompt answered '$answer' declines"
        else
            bad "prompt answered '$answer' declines" "exit status $RC"
        fi
    done
else
    skip "prompt on a terminal" "no script(1) here"
fi

# --- a second Ctrl-C stops at once --------------------------------------------
# Frame 0 of a cheap scene (every ray escapes at once) is rendered in well under
# a second, then its 1200x1200 CSV takes a second or more to write. The first
# SIGINT comes while the CSV is being written (its temporary exists), which
# lets the frame finish; the second must stop at once: no d_0.csv, no
# temporary, exit status 130, well before the write could have finished.
printf 'metric: {m: 1, a: 0, q: 0}\nobserver: {r: 1000, theta: 90, phi: 0, hfov: 60, yaw: 180}\n' >away.yml
rm -rf s2
"$CURRAY" -s away.yml -o s2 -x 1200 -y 1200 -f 3 -t d -a true </dev/null >s2.log 2>&1 &
pid=$!
for _ in $(seq 3000); do [ -n "$(temps_in s2)" ] && break; sleep 0.02; done
kill -INT "$pid" 2>/dev/null
sleep 0.05
t0=$(date +%s.%N)
kill -INT "$pid" 2>/dev/null
for _ in $(seq 1000); do kill -0 "$pid" 2>/dev/null || break; sleep 0.01; done
t1=$(date +%s.%N)
if kill -0 "$pid" 2>/dev/null; then
    kill -KILL "$pid"
    wait "$pid" 2>/dev/null
    OUT=$(cat s2.log)
    bad "second Ctrl-C stops at once" "still running 10 s after the second SIGINT"
else
    wait "$pid"
    RC=$?
    OUT=$(cat s2.log)
    took=$(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.2f", b - a }')
    why=""
    [ "$RC" = 130 ] || why="exit status $RC, expected 130"
    [[ "$OUT" == *"interrupted again: stopped at once"* ]] || why=${why:-"message lacks 'interrupted again: stopped at once'"}
    [ -e s2/d_0.csv ] && why=${why:-"the unfinished frame left d_0.csv"}
    [ -z "$(temps_in s2)" ] || why=${why:-"temporary files left: $(temps_in s2)"}
    # that the frame never finished (no d_0.csv) shows the stop did not wait
    # for it; the time is a bound on "at once" loose enough for a loaded
    # machine (0.72 s seen at a load of 13 on 2 cores). A sanitizer build (it
    # cannot start under ulimit -v) runs a signal handler only at its next
    # intercepted call, which the CSV writer makes seldom
    limit=2
    (ulimit -v 3000000 && "$CURRAY" --version) >/dev/null 2>&1 || limit=6
    awk -v t="$took" -v l="$limit" 'BEGIN { exit !(t < l) }' || why=${why:-"took $took s after the second SIGINT (limit $limit s)"}
    if [ -z "$why" ]; then ok "second Ctrl-C stops at once ($took s)"; else bad "second Ctrl-C stops at once" "$why"; fi
fi
rm -rf s2

# --- curray (no MPI) started by an MPI launcher ------------------------------
# as one of several processes each would render the whole run into one
# folder: refused before anything is written; a launcher's size of 1 is fine
for v in OMPI_COMM_WORLD_SIZE=3 PMI_SIZE=3 MV2_COMM_WORLD_SIZE=3; do
    AS=(env "$v")
    expect "under an MPI launcher ($v)" 1 "was started by an MPI launcher as one of 3 processes ($v), but it is built without MPI: each would render the whole run into the same folder. Under mpirun or srun start curray_mpi instead (mpirun -np 3 curray_mpi" \
        -s good.yml -o o -x 8 -y 8 -a true
done
AS=(env PMIX_RANK=1)
expect "under an MPI launcher (PMIX_RANK=1)" 1 "as one of several processes (PMIX_RANK=1)" -s good.yml -o o -x 8 -y 8 -a true
AS=(env OMPI_COMM_WORLD_SIZE=1 PMI_SIZE=1 PMIX_RANK=0)
rm -rf o
run -s good.yml -o o -x 8 -y 8 -t c -a true
if [ "$RC" = 0 ] && [ -s o/c_0.png ]; then ok "an MPI launcher's single process renders"; else bad "an MPI launcher's single process renders" "rc $RC"; fi
AS=()
rm -rf o

# --- a crash leaves a crash report ---------------------------------------------
# SIGSEGV sent to a running render: <output>/log/crash-<time>-<pid>.log with the
# signal, a backtrace and the run's settings; the process dies by SIGSEGV
# (status 128 + 11 in the shell).
rm -rf cr
"$CURRAY" -s "$ROOT/scenes/demo.yml" -o cr -x 32 -y 32 -f 200 -t ic --threads 1 -a true </dev/null >cr.log 2>&1 &
pid=$!
for _ in $(seq 600); do [ -f cr/info.txt ] && break; sleep 0.1; done
kill -SEGV "$pid" 2>/dev/null
for _ in $(seq 300); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
if kill -0 "$pid" 2>/dev/null; then
    kill -KILL "$pid"
    wait "$pid" 2>/dev/null
    OUT=$(cat cr.log)
    bad "crash report" "still running 30 s after SIGSEGV"
else
    wait "$pid"
    RC=$?
    OUT=$(cat cr.log)
    report=$(ls cr/log/crash-*-"$pid".log 2>/dev/null | head -1)
    why=""
    [ "$RC" = 139 ] || why="exit status $RC, expected 139 (death by SIGSEGV)"
    [ -n "$report" ] || why=${why:-"no cr/log/crash-<time>-$pid.log"}
    if [ -n "$report" ]; then
        [[ "$(basename "$report")" =~ ^crash-[0-9]{8}-[0-9]{6}-$pid\.log$ ]] || why=${why:-"odd name $report"}
        grep -q 'crashed: signal 11, SIGSEGV' "$report" || why=${why:-"report lacks the signal"}
        grep -q '^Backtrace' "$report" || why=${why:-"report lacks a backtrace"}
        grep -Eq 'curray(_cpu)?\(' "$report" || why=${why:-"the backtrace has no curray frame"}
        grep -q "^command line: .*-o cr -x 32 -y 32 -f 200" "$report" || why=${why:-"report lacks the run's settings"}
        [[ "$OUT" == *"crash report in $report"* ]] || why=${why:-"stderr does not name the report"}
    fi
    if [ -z "$why" ]; then ok "crash report (SIGSEGV)"; else bad "crash report" "$why"; [ -n "$report" ] && sed 's/^/       > /' "$report"; fi
fi

echo "$passed passed, $failed failed, $skipped skipped"
[ "$failed" = 0 ]
