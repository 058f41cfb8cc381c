#!/usr/bin/env bash
# Prints the llvmpipe comparison figures (PSNR, per-draw fragment counts) of
# the last ctest run in BUILD_DIR: ctest keeps the output of passing tests
# only in its log, and these figures are the point of those tests.
set -euo pipefail
log="${1:?usage: validation-summary.sh BUILD_DIR}/Testing/Temporary/LastTest.log"
[[ -f "$log" ]] || { echo "validation-summary: no ctest log at $log" >&2; exit 1; }
echo "== validation against llvmpipe (from $log)"
grep -E "^(reference: |SKIPPED: |[^ ].* frame [0-9]+ [0-9]+x[0-9]+: PSNR |  (covered|passed ) fragments: )" "$log" \
  | grep -v "^reference: " || echo "no reference comparison ran"
