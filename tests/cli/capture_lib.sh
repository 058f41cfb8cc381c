# Shared by the capture tests (capture.sh, capture_gl2.sh,
# capture_nexuiz.sh), sourced with `. capture_lib.sh`.

# require_capture_tools GAME: exit 77 (skipped), naming what is missing,
# unless apitrace, glretrace, Xvfb and the game's engine are installed.
require_capture_tools() {
  for tool in apitrace glretrace xvfb-run "$1"; do
    if ! command -v "$tool" >/dev/null 2>&1; then
      echo "skipped: $tool is not installed (scripts/install-deps.sh --capture)"
      exit 77
    fi
  done
}

# counts_match TRACE FIRST LAST CHECK EXTRA_DRAWS EXTRA_TRIANGLES: exit 1
# unless, frame by frame from FIRST to LAST, the draws and triangles of
# `oovr check-capture`'s rows (in the file CHECK) plus EXTRA_DRAWS and
# EXTRA_TRIANGLES (what oovr stands in for otherwise, such as the copy of
# the view into the window) are what `apitrace dump` lists for TRACE
# (tests/cli/dump_counts.awk). Leaves dump.txt and oovr.txt beside CHECK.
counts_match() {
  dir=$(dirname "$4")
  apitrace dump --color=never "$1" 2>/dev/null | awk -v first="$2" -v last="$3" -f "$src/tests/cli/dump_counts.awk" >"$dir/dump.txt"
  awk -v d="$5" -v t="$6" 'NF == 5 && $1 ~ /^[0-9]+$/ && $2 ~ /^[0-9]+$/ { print $1, $2 + d, $3 + t }' "$4" >"$dir/oovr.txt"
  echo "apitrace dump:"
  cat "$dir/dump.txt"
  frames=$(($3 - $2 + 1))
  [ "$(wc -l <"$dir/dump.txt")" -eq "$frames" ] || { echo "apitrace dump listed $(wc -l <"$dir/dump.txt") frames of $2 to $3"; exit 1; }
  if ! cmp -s "$dir/dump.txt" "$dir/oovr.txt"; then
    echo "draws or triangles differ from apitrace dump's:"
    diff "$dir/dump.txt" "$dir/oovr.txt" || true
    exit 1
  fi
}
