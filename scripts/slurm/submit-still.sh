#!/usr/bin/env bash
# Renders one qjulia still on a Slurm cluster: submits a job array whose tasks render its tiles
# (still.sbatch: `qjulia render --tile K/N`, partial EXRs in PARTS_DIR), and the merge job once
# every task has succeeded (still.sbatch with QJULIA_STEP=merge, --dependency=afterok), which
# writes the PNG, byte-identical to one `qjulia render`. Prints the two job ids.
#
#   scripts/slurm/submit-still.sh SCENE PARTS_DIR OUT.png [TILES]
#
#   SCENE      the scene file (TOML, or a PNG or EXR written by qjulia)
#   PARTS_DIR  the folder of the partial EXRs, on storage that every node reads and writes
#   OUT.png    the merged picture
#   TILES      the array's size, the number of bands of rows (default 4; at most the image's
#              height)
#
# Environment:
#   QJULIA_BIN          the qjulia binary the jobs run (default: qjulia on PATH here)
#   QJULIA_OPTS         more qjulia options for the tiles, split at blanks (scene options such as
#                       "--set image.samples=256", "--backend gpu"; the merge takes --backend)
#   QJULIA_HDR          the merged OpenEXR to write as well (optional)
#   QJULIA_STATS        the merged statistics to write as JSON (optional)
#   QJULIA_ARRAY_OPTS   sbatch options for the array, split at blanks
#                       (e.g. "--partition=gpu --gres=gpu:1 --time=01:00:00")
#   QJULIA_MERGE_OPTS   sbatch options for the merge job, split at blanks (default: the array's,
#                       so that the merge asks for a GPU where the tiles did)
# sbatch's own SBATCH_* variables apply to both jobs. Paths are made absolute here, so the jobs
# find them from any working directory.
set -euo pipefail

usage() {
    echo "usage: $0 SCENE PARTS_DIR OUT.png [TILES]" >&2
    exit 2
}
die() {
    echo "submit-still.sh: $*" >&2
    exit 2
}
[[ $# -eq 3 || $# -eq 4 ]] || usage
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
scene=$(realpath -m -- "$1")
parts=$(realpath -m -- "$2")
png=$(realpath -m -- "$3")
tiles=${4:-4}
if ! [[ $tiles =~ ^[0-9]{1,6}$ ]] || (((10#$tiles) < 1 || (10#$tiles) > 65536)); then
    die "TILES must be a whole number from 1 to 65536, not '$tiles'"
fi
tiles=$((10#$tiles))
[[ -f $scene ]] || die "$1: no such scene file"
bin=${QJULIA_BIN:-qjulia}
if [[ $bin == */* ]]; then
    bin=$(realpath -m -- "$bin")
    [[ -x $bin ]] || die "QJULIA_BIN=$QJULIA_BIN is not an executable file"
else
    bin=$(command -v -- "$bin") || die "qjulia is not on PATH: set QJULIA_BIN to the binary"
fi
hdr=${QJULIA_HDR:+$(realpath -m -- "$QJULIA_HDR")}
stats=${QJULIA_STATS:+$(realpath -m -- "$QJULIA_STATS")}
read -r -a array_opts <<<"${QJULIA_ARRAY_OPTS:-}"
read -r -a merge_opts <<<"${QJULIA_MERGE_OPTS-${QJULIA_ARRAY_OPTS:-}}"

# Both jobs take every variable from here (--export=ALL), with the inputs set explicitly.
export QJULIA_SCENE=$scene QJULIA_PARTS=$parts QJULIA_PNG=$png QJULIA_BIN=$bin
export QJULIA_HDR=$hdr QJULIA_STATS=$stats QJULIA_TASKS=$tiles QJULIA_OPTS=${QJULIA_OPTS:-}
mkdir -p -- "$parts"

array=$(QJULIA_STEP=tiles sbatch --parsable --export=ALL --array="0-$((tiles - 1))" \
    "${array_opts[@]}" "$here/still.sbatch")
array=${array%%;*}
merge_job=$(QJULIA_STEP=merge sbatch --parsable --export=ALL --dependency="afterok:$array" \
    --kill-on-invalid-dep=yes "${merge_opts[@]}" "$here/still.sbatch")
merge_job=${merge_job%%;*}
echo "array job $array: $tiles tiles into $parts"
echo "merge job $merge_job: $png, after the array succeeds"
