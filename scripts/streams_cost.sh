#!/bin/bash
# What two streams cost a plain render (issue 49, item 3): the mean squared error of plain Sobol'
# renders of 64 samples a pixel over seeds, binary OLD (every sample from one stream) against
# binary NEW (samples alternating between two independently scrambled streams, whose halves give
# the error estimate), on the path-traced preset, the path-gallery preset and a smooth Lambert
# scene (the unit ball, path traced, no specular lobe).
#
#     scripts/streams_cost.sh OLD NEW [SEEDS] [SIZE] [REF]
#
# Each render is SIZE x SIZE (default 64), `path.seed` 1..SEEDS (default 12). The reference is
# the mean of two renders of REF (default 4096) `random` samples with seeds of their own; its own
# error is taken out of each MSE (examples/adaptive_study.rs, `mse`). Prints per scene and binary
# the MSE (mean over seeds, with its standard error). Needs the example built:
# cargo build --release --example adaptive_study.
set -eu
cd "$(dirname "$0")/.."
[ $# -ge 2 ] || { echo "usage: $0 OLD NEW [SEEDS] [SIZE] [REF]"; exit 2; }
OLD=$1
NEW=$2
SEEDS=${3:-12}
SIZE=${4:-64}
REF=${5:-4096}
# shellcheck source=scripts/mse_common.sh
. scripts/mse_common.sh
for entry in "${scenes[@]}"; do
    name=${entry%%|*}
    args=${entry#*|}
    references "$name" "$args"
    runs=()
    for seed in $(seq "$SEEDS"); do
        render "$OLD" "$WORK/$name-old-$seed" "$args" --set image.samples=64 --set path.seed="$seed"
        render "$NEW" "$WORK/$name-new-$seed" "$args" --set image.samples=64 --set path.seed="$seed"
        runs+=("$WORK/$name-old-$seed.exr" "$WORK/$name-new-$seed.exr")
    done
    "$STUDY" mse "$WORK/$name-ref-a.exr" "$WORK/$name-ref-b.exr" "${runs[@]}" >"$WORK/$name.mse"
    for binary in old new; do
        grep -- "-$binary-" "$WORK/$name.mse" | awk -v name="$name" -v binary="$binary" '
            {m += $2; q += $2 * $2; n++}
            END {mean = m / n; se = sqrt((q / n - mean * mean) / (n - 1))
                 printf "%s, %s: mse %.4e +- %.1e\n", name, binary, mean, se}'
    done
done
