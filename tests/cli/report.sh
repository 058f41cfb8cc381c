#!/bin/sh
# `oovr report` on a small sweep: the page, its tables and plots (PNG and
# SVG) are written; with --browser, headless Chromium opens the page, its
# screenshot must not be blank and its tables must be there. Exits 77
# ("skipped", with the reason) when --browser is asked and Chromium is not
# installed (scripts/install-deps.sh --services installs it).
# Usage: report.sh OOVR WORKDIR [--browser]
set -eu
oovr=$1
work=$2
browser=${3:-}
if [ "$browser" = --browser ]; then
  command -v chromium > /dev/null 2>&1 || { echo "skipped: chromium is not installed (scripts/install-deps.sh --services)"; exit 77; }
fi
rm -rf "$work" && mkdir -p "$work" && cd "$work"
export OOVR_CACHE_DIR="$work/cache"
cat > small.toml <<'TOML'
name = "small"
scenes = ["crowd"]
schemes = ["baseline", "object", "oo-vr"]
resolutions = ["160x128"]
frames = 8
images = true
[sweep]
gpms = [2, 4, 8]
TOML
"$oovr" sweep small.toml --db small.db > sweep.log 2>&1 || { cat sweep.log; exit 1; }
# A second sweep into the same database whose text, scene name and error
# carry markup that would run script if written into the page unescaped.
cat > evil.toml <<'TOML'
# </pre><script>document.title='PWNED'</script>
name = "evil"
description = "<script>document.title='PWNED'</script>"
scenes = ["<img src=x onerror=\"document.title='PWNED'\">.obj"]
schemes = ["baseline"]
resolutions = ["160x128"]
frames = 4
TOML
if "$oovr" sweep evil.toml --db small.db > evil.log 2>&1; then echo "the missing scene ran"; exit 1; fi
grep -q "1 failed" evil.log || { cat evil.log; exit 1; }
"$oovr" report small.db --out rep > report.log 2>&1 || { cat report.log; exit 1; }
grep -q "&lt;img src=x onerror=" rep/index.html || { echo "the scene's name is not in the page, escaped"; exit 1; }
if grep -q "<img src=x\|<script" rep/index.html; then echo "markup from the database reached the page unescaped"; exit 1; fi
grep -q "^report: rep/index.html$" report.log || { cat report.log; exit 1; }
for f in index.html report.py claims.json sweep-small-gpms.png sweep-small-gpms.svg \
         paper-figure-15-speed-up-over-the-baseline.png paper-figure-16-inter-gpm-traffic-against-the-baseline.svg; do
  [ -s "rep/$f" ] || { echo "missing rep/$f"; ls rep; exit 1; }
done
[ "$(ls rep/images-*.png | wc -l)" -eq 3 ] || { echo "not one image per scheme"; ls rep; exit 1; }
grep -q "<h2>The paper's claims</h2>" rep/index.html || exit 1
grep -q "<h2>Sweep small</h2>" rep/index.html || exit 1
# The object-level P7 claim matches the 4-GPM runs; the 8-GPM P14 ones need single-gpm, absent here.
grep -q "<td>P7</td><td>object</td>" rep/index.html || exit 1
grep -q "no matching runs" rep/index.html || exit 1
# Each claim's checks judged on the same runs: P7's on the means of the
# 4-GPM runs; P14's need single-gpm, so they are not measured.
grep -Eq "<tr><td>P7, direction</td>.*<td>(agrees|differs)</td><td></td></tr>" rep/index.html || { echo "P7 not judged"; exit 1; }
grep -q "<tr><td>P14, direction</td>.*<td>not measured</td>" rep/index.html || { echo "P14 judged without its runs"; exit 1; }
# The schemes' colours are oovr's, the paper charts' (svg_chart.h), handed to the script.
grep -q '"scheme_colours": {' rep/claims.json && grep -q '"baseline": "#1f77b4"' rep/claims.json || { echo "no scheme colours"; exit 1; }
# Energy is in the study's table and figure (each run's memory-system energy).
grep -q "<th>energy (mJ/frame)</th>" rep/index.html || { echo "no energy column"; exit 1; }
grep -q "frame latency, speed-up over baseline, inter-GPM traffic, memory-system energy against gpms" rep/index.html ||
  { echo "the figure does not have the default rows"; exit 1; }
# The options, drawn: two rows, panels per scheme, speed-ups over OO-VR.
"$oovr" report small.db --out opt --plots energy,speedup --group scheme --normalise oo-vr --own-y > opt.log 2>&1 ||
  { cat opt.log; exit 1; }
grep -q "memory-system energy, speed-up over oo-vr against gpms, per scheme" opt/index.html || { echo "options not drawn"; exit 1; }
grep -q "<th>speed-up over oo-vr</th>" opt/index.html || exit 1
grep -q '"normalise": "oo-vr"' opt/claims.json || exit 1
# Options naming what the database does not have: one clear error each, nothing written.
for bad in "--plots joules:no plot 'joules'" "--x link.bandwidth:do not sweep 'link.bandwidth' (they sweep gpms)" \
           "--normalise afr:no done runs of 'afr'" "--group eye:--group: eye not in"; do
  flag=${bad%%:*}
  if "$oovr" report small.db --out badopt $flag > badopt.log 2>&1; then echo "reported with $flag"; exit 1; fi
  grep -qF -e "${bad#*:}" badopt.log || { echo "$flag:"; cat badopt.log; exit 1; }
  [ ! -e badopt ] || { echo "$flag wrote the folder"; exit 1; }
done
# A key swept with words, not numbers, is no figure's x axis: said, not silently left out.
cat > words.toml <<'TOML'
name = "words"
scenes = ["crowd"]
schemes = ["baseline"]
resolutions = ["160x128"]
frames = 1
[sweep]
"memory.placement" = ["first-touch", "interleaved"]
TOML
"$oovr" sweep words.toml --db words.db > words.log 2>&1 || { cat words.log; exit 1; }
if "$oovr" report words.db --out wordsrep --x memory.placement > wordsrep.log 2>&1; then echo "plotted against words"; exit 1; fi
grep -q "'memory.placement' is swept with values that are not numbers" wordsrep.log || { cat wordsrep.log; exit 1; }
# A database that is not one: one clear error.
echo "not a database" > bad.db
if "$oovr" report bad.db --out bad > bad.log 2>&1; then echo "reported a bad database"; exit 1; fi
grep -q "^oovr: error: .*bad.db" bad.log || { cat bad.log; exit 1; }
if [ "$browser" != --browser ]; then
  echo "report written: $(ls rep | wc -l) files"
  exit 0
fi

run_chromium() {
  chromium --headless --no-sandbox --disable-gpu --no-first-run --disable-background-networking \
    --user-data-dir="$work/profile" --window-size=1200,900 "$@" 2> chromium.err
}
run_chromium --screenshot="$work/shot.png" "file://$work/rep/index.html" > /dev/null || { tail chromium.err; exit 1; }
run_chromium --dump-dom "file://$work/rep/index.html" > dom.html || { tail chromium.err; exit 1; }
[ -s shot.png ] || { echo "no screenshot"; exit 1; }
# Not blank: many colours, and a good share of the page is not background.
/usr/bin/python3 - "$work/shot.png" <<'PY'
import sys
import matplotlib.image as mpimg
import numpy as np
img = mpimg.imread(sys.argv[1])[:, :, :3]
colours = len(np.unique((img * 255).astype(np.uint8).reshape(-1, 3), axis=0))
inked = float((img.sum(axis=2) < 2.9).mean())
print("screenshot: %dx%d, %d colours, %.1f%% not white" % (img.shape[1], img.shape[0], colours, 100 * inked))
sys.exit(0 if colours > 50 and inked > 0.02 else 1)
PY
tables=$(grep -o "<table" dom.html | wc -l)
[ "$tables" -ge 2 ] || { echo "the page has $tables tables"; exit 1; }
grep -q "oovr report" dom.html || exit 1
# Nothing from the database ran: the title is the page's own.
grep -q "<title>oovr report</title>" dom.html || { echo "the page's title was changed: script ran"; exit 1; }
if grep -q PWNED dom.html && ! grep -q "&lt;img src=x onerror=" dom.html; then echo "markup ran in Chromium"; exit 1; fi
grep -q "<img src=\"sweep-small-gpms.png\"" dom.html || exit 1
# Each figure as Chromium draws its SVG (the page links them), kept beside
# the page's screenshot to be looked at: none blank.
figures=0
for svg in rep/sweep-*.svg rep/paper-*.svg opt/sweep-*.svg; do
  name=$(basename "$(dirname "$svg")")-$(basename "$svg" .svg)
  run_chromium --screenshot="$work/figure-$name.png" --window-size=1400,1400 "file://$work/$svg" > /dev/null ||
    { tail chromium.err; exit 1; }
  /usr/bin/python3 - "$work/figure-$name.png" <<'PY' || { echo "figure $svg is blank in Chromium"; exit 1; }
import sys
import matplotlib.image as mpimg
import numpy as np
img = mpimg.imread(sys.argv[1])[:, :, :3]
colours = len(np.unique((img * 255).astype(np.uint8).reshape(-1, 3), axis=0))
sys.exit(0 if colours > 20 and float((img.sum(axis=2) < 2.9).mean()) > 0.01 else 1)
PY
  figures=$((figures + 1))
done
[ "$figures" -ge 4 ] || { echo "only $figures figures drawn"; exit 1; }
echo "Chromium shows the report: $tables tables, $figures figures (figure-*.png), markup from the database shown as text, not run"
