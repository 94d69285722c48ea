# Shared helpers of the issue-14 CLI test scripts (test_resume.sh,
# test_video.sh, test_mpi.sh); source it with the script's name:
#   . "$(dirname "$0")/lib.sh" NAME
# It makes a temporary folder, removed at exit, and changes into it.
# ok NAME / bad NAME WHY: a case passed / failed (bad shows what the last run
# printed); run ARGS: runs $CURRAY (stdin not a terminal, 120 s at most)
# into OUT and RC; has TEXT: OUT contains TEXT; finish: the last line and the
# exit status.
WORK=$(mktemp -d "${TMPDIR:-/tmp}/curray-$1.XXXXXX")
trap 'rm -rf "$WORK"' EXIT
cd "$WORK" || exit 2
passed=0 failed=0
OUT="" RC=0
ok() { echo "ok   $1"; passed=$((passed + 1)); }
bad() { echo "FAIL $1: $2"; [ -n "$OUT" ] && echo "$OUT" | sed 's/^/       | /'; failed=$((failed + 1)); }
run() { OUT=$(timeout 120 "$CURRAY" "$@" </dev/null 2>&1); RC=$?; }
has() { case "$OUT" in *"$1"*) return 0 ;; *) return 1 ;; esac; }
finish() { echo "$passed passed, $failed failed"; [ $failed = 0 ]; }
# refused NAME TEXT ARGS...: curray ARGS exits with status 1 saying TEXT
refused() {
    local name=$1 text=$2
    shift 2
    run "$@"
    if [ $RC = 1 ] && has "$text"; then ok "$name"; else bad "$name" "rc $RC"; fi
}
