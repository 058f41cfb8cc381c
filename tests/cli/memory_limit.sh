#!/bin/sh
# Under a cgroup's memory limit (a container's, a SLURM job's) the kernel
# answers an allocation past the limit with SIGKILL, not an error. oovr
# estimates the memory system's state before allocating it and refuses
# what the cgroup's room cannot hold with a clear error; a sweep holding
# such a point records it as failed and finishes the others. Makes a
# memory cgroup of 300 MB (v1 or v2, as root); exits 77 ("skipped", with
# the reason) where none can be made. Usage: memory_limit.sh OOVR WORKDIR
set -eu
oovr=$1
work=$2
skip() { echo "skipped: $*"; exit 77; }
rm -rf "$work" && mkdir -p "$work" && cd "$work"
export OOVR_CACHE_DIR="$work/cache"
if [ -f /sys/fs/cgroup/cgroup.controllers ]; then
  cg=/sys/fs/cgroup/oovr-test-$$
  mkdir "$cg" 2> /dev/null || skip "cannot make a cgroup under /sys/fs/cgroup (not root, or delegated elsewhere)"
  echo 300M > "$cg/memory.max" || skip "the cgroup has no memory controller"
  limit_file=memory.max
elif [ -d /sys/fs/cgroup/memory ]; then
  cg=/sys/fs/cgroup/memory/oovr-test-$$
  mkdir "$cg" 2> /dev/null || skip "cannot make a memory cgroup under /sys/fs/cgroup/memory (not root?)"
  echo 300M > "$cg/memory.limit_in_bytes" || skip "cannot set the cgroup's memory limit"
  limit_file=memory.limit_in_bytes
else
  skip "no cgroup file system at /sys/fs/cgroup"
fi
cleanup() { rmdir "$cg" 2> /dev/null || true; }
trap cleanup EXIT
# Runs the rest of its words inside the cgroup.
in_cgroup() { sh -c 'echo $$ > "$0/cgroup.procs" && exec "$@"' "$cg" "$@"; }
cat > m.toml <<'TOML'
name = "m"
scenes = ["crowd"]
schemes = ["baseline"]
resolutions = ["160x128"]
frames = 4
# At 1,024 SMs a GPM, 4,096 L1s of 16,384 lines: 512 MB of tags at 8
# bytes a line (LRU's recency-ordered sets), past the cgroup's 300 MB.
[sweep]
"gpm.sms" = [8, 1024]
"cache.l1.size" = ["2MB"]
TOML
rc=0
in_cgroup "$oovr" simulate --scene crowd --scheme baseline --resolution 64x64 --set gpms=32 --set gpm.sms=1024 \
  --set cache.l1.size=1MB > one.log 2>&1 || rc=$?
[ $rc -eq 1 ] || { cat one.log; echo "simulate: exit status $rc, not 1 (137 is the OOM killer's SIGKILL)"; exit 1; }
grep -q "^oovr: error: the memory system .* needs about .* GB, more than the .* this process may still use (the cgroup's $limit_file, 300 MB)" one.log || {
  cat one.log; exit 1; }
rc=0
in_cgroup "$oovr" sweep m.toml --db m.db > sweep.log 2>&1 || rc=$?
[ $rc -eq 1 ] || { cat sweep.log; echo "sweep: exit status $rc"; exit 1; }
[ "$(sqlite3 m.db "SELECT status FROM runs ORDER BY position" | tr '\n' ' ')" = "done failed " ] || {
  sqlite3 m.db "SELECT position, status, error FROM runs"; exit 1; }
sqlite3 m.db "SELECT error FROM runs WHERE status = 'failed'" | grep -q "the cgroup's $limit_file" || exit 1
echo "under a 300 MB cgroup: refused before allocating, the sweep's other point done"
