#!/usr/bin/env bash
# moire farm on a real Slurm: a single-node cluster started here (cluster.sh), a 48-frame
# clip submitted in 6 shards, numbered frames in 3 and a 4-tile poster, each compared byte for
# byte with the same request rendered locally; and a failing shard, whose join is cancelled.
#   slurm_test.sh MOIRE_BINARY
# Exits 77 (ctest: skipped), saying why, when it cannot be root, Slurm or munge is missing, or
# there is no cgroup filesystem for slurmd.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
moire=$(realpath "$1")
export PATH=$PATH:/usr/sbin:/sbin

if [[ $(id -u) -ne 0 ]]; then
  if sudo -n true 2>/dev/null; then exec sudo -n --preserve-env=PATH bash "$0" "$@"; fi
  echo "skipped: starting Slurm's daemons needs root (or sudo without a password)"
  exit 77
fi
for tool in munged slurmctld slurmd sbatch scontrol sinfo ffmpeg; do
  if ! command -v "$tool" >/dev/null; then
    echo "skipped: $tool is not installed (scripts/deps.sh installs slurm-wlm, munge and ffmpeg)"
    exit 77
  fi
done
# slurmd reads the cgroup filesystem as it starts, whatever plugins are configured; a chroot
# that bound /sys without what is mounted under it has none.
if ! mountpoint -q /sys/fs/cgroup; then
  echo "skipped: slurmd needs a cgroup filesystem and /sys/fs/cgroup has none mounted here"
  exit 77
fi

tmp=$(mktemp -d)
source "$here/cluster.sh"
finish() {
  local status=$?
  stop_cluster "$tmp/cluster"
  if [[ $status -ne 0 ]]; then
    echo "--- the jobs' logs:" >&2
    tail -n 20 "$tmp"/work-*/logs/*.log >&2 2>/dev/null || true
  fi
  rm -rf "$tmp"
  exit $status
}
trap finish EXIT
start_cluster "$tmp/cluster"

# The job id of a submission's join, from the line submit.sh prints.
join_id() { sed -n 's/.*join: job \([0-9]*\).*/\1/p' "$1"; }

# Waits for job $1 to end (60 s at most); fails unless it completed.
wait_for() {
  local state=""
  for _ in $(seq 1 300); do
    state=$(scontrol show job -o "$1" | sed -n 's/.*JobState=\([A-Z_]*\).*/\1/p')
    case $state in
      COMPLETED) return 0 ;;
      FAILED | CANCELLED | TIMEOUT | NODE_FAIL | OUT_OF_MEMORY)
        echo "FAIL: job $1 ended $state" >&2
        return 1
        ;;
    esac
    sleep 0.2
  done
  echo "FAIL: job $1 still $state after 60 s" >&2
  return 1
}

# The clip: 48 frames of the default scene in 6 shards of 8 frames, joined into one H.264
# video by one encode, as `moire clip` makes it.
clip=(--fps 24 --frames 48 --size 64x48)
"$moire" farm clip "${clip[@]}" --shards 6 --workdir "$tmp/work-clip" \
  -o "$tmp/farm/clip.mp4" -q | tee "$tmp/clip.out"
clip_join=$(join_id "$tmp/clip.out")

# Numbered images: the shards write them in place; the join only reports them.
frames=(--fps 24 --size 64x48 --frames 12..23)
"$moire" farm clip "${frames[@]}" --shards 3 --workdir "$tmp/work-frames" \
  -o "$tmp/farm/frames/f_%03d.png" -q | tee "$tmp/frames.out"
frames_join=$(join_id "$tmp/frames.out")

# The poster: 4 tiles (2 x 2) of a 16-bit TIFF, each rendered with --region, assembled.
poster=(--size 96x64 --depth 16 --time 0.5)
"$moire" farm render "${poster[@]}" --shards 4 --workdir "$tmp/work-poster" \
  -o "$tmp/farm/poster.tif" -q | tee "$tmp/poster.out"
poster_join=$(join_id "$tmp/poster.out")

# A shard that fails: Slurm cancels the join, nothing is written, and --wait says so.
cat >"$tmp/flaky" <<FLAKY
#!/bin/bash
[[ \${SLURM_ARRAY_TASK_ID:-} == 1 ]] && exit 1
exec "$moire" "\$@"
FLAKY
chmod +x "$tmp/flaky"
status=0
"$moire" farm clip "${clip[@]}" --shards 3 --workdir "$tmp/work-flaky" --moire "$tmp/flaky" \
  -o "$tmp/farm/flaky.mp4" --wait >"$tmp/flaky.out" 2>&1 || status=$?
if [[ $status != 3 ]] || ! grep -q "the join did not succeed" "$tmp/flaky.out"; then
  echo "FAIL: farm --wait with a failed shard exited $status:" >&2
  cat "$tmp/flaky.out" >&2
  exit 1
fi
[[ ! -e "$tmp/farm/flaky.mp4" ]]
echo "ok: a failed shard cancels the join, and --wait reports it"

# The same requests rendered here, while the cluster works.
"$moire" clip "${clip[@]}" -o "$tmp/local/clip.mp4" -q
"$moire" clip "${frames[@]}" -o "$tmp/local/frames/f_%03d.png" -q
"$moire" render "${poster[@]}" -o "$tmp/local/poster.tif" -q

wait_for "$poster_join"
cmp "$tmp/farm/poster.tif" "$tmp/local/poster.tif"
[[ $(ls "$tmp/work-poster/logs" | grep -c '^shard-') == 4 ]]
echo "ok: a poster in 4 tiles is byte for byte the local render"

wait_for "$frames_join"
diff -r "$tmp/farm/frames" "$tmp/local/frames"
[[ $(ls "$tmp/farm/frames" | wc -l) == 12 ]]
echo "ok: 12 numbered frames in 3 shards are the local frames"

wait_for "$clip_join"
cmp "$tmp/farm/clip.mp4" "$tmp/local/clip.mp4"
[[ $(ls "$tmp/work-clip/logs" | grep -c '^shard-') == 6 ]]
echo "ok: a 48-frame clip in 6 shards is byte for byte the local clip"
