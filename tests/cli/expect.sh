#!/bin/sh
# Runs one command and checks both its exit status and its output, so that a
# command-line test cannot pass on the wrong one (CTest's
# PASS_REGULAR_EXPRESSION alone ignores the exit status).
#
#   expect.sh CMAKE EXPECT REGEX SKIP -- COMMAND ARGS...
#
# EXPECT ok     the command must exit 0 and its output (stdout and stderr
#               together) match REGEX.
#        error  the command must exit from 1 to 125, but not 77 (a crash or
#               a signal is not an error message), and its output match
#               REGEX.
#        skip   as ok, but the command's own "skipped" (exit 77) is passed
#               on as 77, for CTest's SKIP_RETURN_CODE.
# SKIP          "-" for none; else a command that exits non-zero with output
#               matching SKIP is reported skipped (exit 77): data that is
#               not installed. Anchor it to the one line that says so.
# REGEX and SKIP are CMake regular expressions, as PASS_REGULAR_EXPRESSION's
# (^ and $ are the start and end of the whole output; . matches newlines),
# matched by tests/cli/match.cmake with the CMAKE given.
set -u
cmake=$1
expect=$2
regex=$3
skip=$4
[ "$skip" = "-" ] && skip=
[ "$5" = "--" ] || { echo "expect.sh: usage: expect.sh CMAKE EXPECT REGEX SKIP -- COMMAND..."; exit 2; }
shift 5
here=$(dirname "$0")
out=$(mktemp "${TMPDIR:-/tmp}/oovr-expect.XXXXXX") || exit 2
trap 'rm -f "$out"' EXIT
"$@" > "$out" 2>&1
rc=$?
cat "$out"
matches() { "$cmake" -DFILE="$out" -DREGEX="$1" -P "$here/match.cmake" > /dev/null 2>&1; }
fail() { echo "expect.sh: FAILED: $1"; exit 1; }
if [ -n "$skip" ] && [ $rc -ne 0 ] && matches "$skip"; then
  echo "expect.sh: skipped: exit $rc, output matches '$skip'"
  exit 77
fi
case $expect in
  ok) [ $rc -eq 0 ] || fail "exit status $rc, expected 0" ;;
  skip)
    [ $rc -eq 77 ] && exit 77
    [ $rc -eq 0 ] || fail "exit status $rc, expected 0 (or 77: skipped)" ;;
  error)
    [ $rc -ne 0 ] || fail "exit status 0, expected an error"
    [ $rc -le 125 ] && [ $rc -ne 77 ] || fail "exit status $rc: a crash, a signal or a skip, not an error message" ;;
  *) echo "expect.sh: EXPECT is ok, error or skip, not '$expect'"; exit 2 ;;
esac
matches "$regex" || fail "the output does not match '$regex'"
exit 0
