#!/usr/bin/env bash
# Render a scene on a Slurm cluster: a job array renders tile i of N on array task i
# (qrm render --tile i/N), and a merge job, which starts only when every tile has succeeded,
# puts the tiles back together (qrm merge). The merged result is byte-identical to one
# `qrm render` with the same flags on one machine: every pixel and cell has a random stream of
# its own, so neither the tiling nor the thread count changes a value.
#
#   examples/slurm/render_array.sh TILES OUT_DIR [qrm render flags, without --tile and --out]
#
#   examples/slurm/render_array.sh 16 out/cornell64 --scene cornell --voxels 64 --width 512 --height 512
#
# Writes OUT_DIR/parts/ (the tiles), OUT_DIR/ (the merged images and summary) and
# OUT_DIR/slurm/ (one log per job and task). Prints the two job ids, array first.
#
# Environment:
#   QRM             the qrm executable (default: qrm on PATH); it must be reachable from the
#                   compute nodes, as must OUT_DIR (a shared file system)
#   SBATCH_FLAGS    extra sbatch flags for both jobs, e.g. "--partition=long --time=02:00:00"
#   SBATCH_ARRAY_FLAGS  extra sbatch flags for the render tasks only, e.g. "--cpus-per-task=8"
#                   (each task renders with --threads = the CPUs Slurm allocated it, default 1)
set -euo pipefail

usage() {
  echo "$1" >&2
  echo "usage: render_array.sh TILES OUT_DIR [qrm render flags, without --tile, --out and --threads]" >&2
  exit 2
}

(($# >= 2)) || usage "render_array.sh: need TILES and OUT_DIR"
tiles=$1
out=$2
shift 2
[[ $tiles =~ ^[1-9][0-9]*$ ]] || usage "render_array.sh: TILES must be a positive integer, got '$tiles'"
for a in "$@"; do
  case $a in
    --tile | --tile=* | --out | --out=*) usage "render_array.sh: do not pass ${a%%=*}: the script sets it (tile i/$tiles, $out)" ;;
    --threads | --threads=*) usage "render_array.sh: do not pass --threads: each task uses the CPUs Slurm allocates it" ;;
  esac
done
command -v sbatch >/dev/null || { echo "render_array.sh: sbatch not found (is Slurm installed here?)" >&2; exit 1; }
qrm=$(command -v "${QRM:-qrm}") || { echo "render_array.sh: qrm not found (set QRM to the executable)" >&2; exit 1; }
qrm=$(realpath "$qrm")

mkdir -p "$out/parts" "$out/slurm"
out=$(realpath "$out")

# The render flags, quoted for the shell that runs the job; progress lines in the task logs
# (every 10 s) unless the flags say --quiet.
flags=""
progress=" --progress"
for a in "$@"; do
  flags+=" $(printf '%q' "$a")"
  [[ $a != --quiet && $a != --progress ]] || progress=""
done
flags+=$progress
q_qrm=$(printf '%q' "$qrm")
q_out=$(printf '%q' "$out")

# shellcheck disable=SC2086  # SBATCH_FLAGS is a list of flags
array_id=$(sbatch --parsable ${SBATCH_FLAGS:-} ${SBATCH_ARRAY_FLAGS:-} --job-name=qrm-render \
  --array=0-$((tiles - 1)) --output="$out/slurm/render_%A_%a.log" \
  --wrap="exec $q_qrm render$flags --tile \$SLURM_ARRAY_TASK_ID/$tiles --threads \${SLURM_CPUS_PER_TASK:-1} --out $q_out/parts")
array_id=${array_id%%;*}  # --parsable prints "id" or "id;cluster"

# afterok: only if every task succeeded; kill-on-invalid-dep: if one failed, the merge job is
# cancelled instead of waiting forever.
# shellcheck disable=SC2086
merge_id=$(sbatch --parsable ${SBATCH_FLAGS:-} --job-name=qrm-merge --dependency=afterok:"$array_id" \
  --kill-on-invalid-dep=yes --output="$out/slurm/merge_%j.log" \
  --wrap="exec $q_qrm merge --parts $q_out/parts --out $q_out")
merge_id=${merge_id%%;*}

echo "$array_id $merge_id"
echo "render_array.sh: $tiles tiles in job array $array_id, merge in job $merge_id; logs in $out/slurm/" >&2
