#!/usr/bin/env bash
# moire farm on a real Slurm: a single-node cluster started here (cluster.sh), a 48-frame
# clip submitted in 6 shards and a 4-tile poster, each compared byte for byte with the same
# request rendered locally.
#   slurm_test.sh MOIRE_BINARY
# Exits 77 (ctest: skipped), saying why, when it cannot be root or Slurm or munge is missing.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
moire=$(realpath "$1")
export PATH=$PATH:/usr/sbin:/sbin

if [[ $(id -u) -ne 0 ]]; then
  if sudo -n true 2>/dev/null; then exec sudo -n --preserve-env=PATH bash "$0" "$@"; fi
  echo "skipped: starting Slurm's daemons needs root (or sudo without a password)"
  exit 77
fi
for tool in munged slurmctld slurmd sbatch scontrol sinfo ffmpeg python3; do
  if ! command -v "$tool" >/dev/null; then
    echo "skipped: $tool is not installed (scripts/deps.sh installs slurm-wlm, munge and ffmpeg)"
    exit 77
  fi
done

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
  -o "$tmp/farm/clip.mp4" | tee "$tmp/clip.out"
clip_join=$(join_id "$tmp/clip.out")

"$moire" clip "${clip[@]}" -o "$tmp/local/clip.mp4" -q
wait_for "$clip_join"
cmp "$tmp/farm/clip.mp4" "$tmp/local/clip.mp4"
[[ $(ls "$tmp/work-clip/logs" | grep -c '^shard-') == 6 ]]
echo "ok: a 48-frame clip in 6 shards is byte for byte the local clip"
