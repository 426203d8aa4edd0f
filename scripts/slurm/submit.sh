#!/usr/bin/env bash
# Renders a qjulia animation on a Slurm cluster: submits a job array whose tasks render the
# frames in contiguous ranges (animate.sbatch), and a job that encodes the video once every task
# has succeeded (video.sbatch, --dependency=afterok). Prints the two job ids.
#
#   scripts/slurm/submit.sh SCENE OUT_DIR VIDEO [TASKS]
#
#   SCENE     the scene file (TOML, or a PNG written by qjulia)
#   OUT_DIR   the frames folder (DIR/frame-NNNNN.png), on storage that every node reads and writes
#   VIDEO     the video file, FILE.mp4 or FILE.webm
#   TASKS     the array's size (default 4; more tasks than frames are trimmed to one per frame)
#
# Environment:
#   QJULIA_FRAMES       the animation's frame count (default: what `qjulia animate --frame-count`
#                       says of the scene and QJULIA_OPTS, asked here on the submitting host)
#   QJULIA_BIN          the qjulia binary the jobs run (default: qjulia on PATH here)
#   QJULIA_OPTS         more qjulia options for both jobs, split at blanks (scene options such as
#                       "--set image.samples=4"; "--backend gpu" makes the video job need a GPU)
#   QJULIA_ARRAY_OPTS   sbatch options for the array, split at blanks
#                       (e.g. "--partition=gpu --gres=gpu:1 --time=01:00:00")
#   QJULIA_VIDEO_OPTS   sbatch options for the video job, split at blanks
# sbatch's own SBATCH_* variables apply to both jobs. Paths are made absolute here, so the jobs
# find them from any working directory.
set -euo pipefail

usage() {
    echo "usage: $0 SCENE OUT_DIR VIDEO [TASKS]" >&2
    exit 2
}
die() {
    echo "submit.sh: $*" >&2
    exit 2
}
[[ $# -eq 3 || $# -eq 4 ]] || usage
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
scene=$(realpath -m -- "$1")
out=$(realpath -m -- "$2")
video=$(realpath -m -- "$3")
tasks=${4:-4}
count() { # NAME VALUE: a whole number from 1 to 100000, printed without leading zeros
    if ! [[ $2 =~ ^[0-9]{1,6}$ ]] || (((10#$2) < 1 || (10#$2) > 100000)); then
        die "$1 must be a whole number from 1 to 100000, not '$2'"
    fi
    echo $((10#$2))
}
tasks=$(count TASKS "$tasks")
[[ -f $scene ]] || die "$1: no such scene file"
case $video in
*.mp4 | *.webm) ;;
*) die "$3: the video must be FILE.mp4 or FILE.webm" ;;
esac
bin=${QJULIA_BIN:-qjulia}
if [[ $bin == */* ]]; then
    bin=$(realpath -m -- "$bin")
    [[ -x $bin ]] || die "QJULIA_BIN=$QJULIA_BIN is not an executable file"
else
    bin=$(command -v -- "$bin") || die "qjulia is not on PATH: set QJULIA_BIN to the binary"
fi
read -r -a opts <<<"${QJULIA_OPTS:-}"
# The frame count, from the scene itself (a bad scene stops here, with qjulia's own error).
frames=${QJULIA_FRAMES:-$("$bin" animate --scene "$scene" "${opts[@]}" --frame-count)} ||
    die "qjulia could not read the scene (above)"
frames=$(count QJULIA_FRAMES "$frames")
((tasks <= frames)) || tasks=$frames
read -r -a array_opts <<<"${QJULIA_ARRAY_OPTS:-}"
read -r -a video_opts <<<"${QJULIA_VIDEO_OPTS:-}"

# Both jobs take every variable from here (--export=ALL), with the inputs set explicitly.
export QJULIA_SCENE=$scene QJULIA_OUT=$out QJULIA_VIDEO=$video QJULIA_BIN=$bin
export QJULIA_FRAMES=$frames QJULIA_TASKS=$tasks QJULIA_OPTS=${QJULIA_OPTS:-}

array=$(sbatch --parsable --export=ALL --array="0-$((tasks - 1))" "${array_opts[@]}" \
    "$here/animate.sbatch")
array=${array%%;*}
video_job=$(sbatch --parsable --export=ALL --dependency="afterok:$array" --kill-on-invalid-dep=yes \
    "${video_opts[@]}" "$here/video.sbatch")
video_job=${video_job%%;*}
echo "array job $array: $tasks tasks, frames 0..$((frames - 1)) into $out"
echo "video job $video_job: $video, after the array succeeds"
