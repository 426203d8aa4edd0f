#!/bin/bash
# Our denoiser against Intel Open Image Denoise 2.5 (issue 49, item 2's table): for the
# path-traced, path-gallery and environment presets at SIZE x SIZE (default 128), renders of 4
# and 16 samples with `image.denoise = "atrous"` over seeds 1..SEEDS (default 4), each denoised
# by us and by OIDN (pyoidn, on our --hdr noisy colour, albedo and normal), in linear RMSE
# against REF (default 1024) `random` samples; the mean over the seeds of each and their
# quotient. Then the 64x64 comparison: 16 denoised samples against 64 raw ones, in linear RMSE
# and in the RMSE of the 8-bit PNG (values over 255), against REF `random` samples, the mean
# over the seeds.
#
#     scripts/oidn_table.sh [BINARY] [SEEDS] [SIZE] [REF]
#
# Needs numpy, OpenEXR and pyoidn (pip install numpy OpenEXR pyoidn); none of the tests use it.
set -eu
cd "$(dirname "$0")/.."
BIN=${1:-target/release/qjulia}
SEEDS=${2:-4}
SIZE=${3:-128}
REF=${4:-1024}
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
render() { # preset, size, output stem, keys...
    local preset=$1 size=$2 out=$3
    shift 3
    "$BIN" render --preset "$preset" --width "$size" --height "$size" --hdr "$out.exr" \
        -o "$out.png" "$@" >/dev/null 2>&1
}
random=(--set 'path.sampler="random"' --set path.seed=1000001 --set "image.samples=$REF"
    --set 'image.denoise="none"' --set path.noise_target=0)
echo "| preset | samples | ours | OIDN | ours / OIDN |"
echo "|---|---|---|---|---|"
for preset in path-traced path-gallery environment; do
    render "$preset" "$SIZE" "$WORK/$preset-ref" "${random[@]}"
    for samples in 4 16; do
        runs=()
        for seed in $(seq 1 "$SEEDS"); do
            out="$WORK/$preset-$samples-$seed"
            render "$preset" "$SIZE" "$out" --set "image.samples=$samples" \
                --set 'image.denoise="atrous"' --set "path.seed=$seed"
            runs+=("$out.exr")
        done
        python3 scripts/exr_stats.py oidn "$WORK/$preset-ref.exr" "${runs[@]}" |
            awk -v p="$preset" -v n="$samples" '
                # "PATH: noisy N (T), ours O (T), OIDN D (T); ours / OIDN Q": the first of each.
                { o += $6; d += $9; m++ }
                END { printf "| %s | %d | %.5f | %.5f | %.3fx |\n", p, n, o / m, d / m, o / d }'
    done
done
echo
echo "64x64, the path-traced preset, against $REF random samples (mean over $SEEDS seeds):"
render path-traced 64 "$WORK/small-ref" "${random[@]}"
for way in "16 atrous" "64 none"; do
    set -- $way
    runs=()
    for seed in $(seq 1 "$SEEDS"); do
        out="$WORK/small-$1-$2-$seed"
        render path-traced 64 "$out" --set "image.samples=$1" --set "image.denoise=\"$2\"" \
            --set "path.seed=$seed"
        runs+=("$out")
    done
    python3 scripts/exr_stats.py png-rmse "$WORK/small-ref" "${runs[@]}" |
        awk -v w="$1 samples, denoise $2" '
            { l += $2; p += $4; m++ }
            END { printf "- %s: linear RMSE %.5f, 8-bit PNG RMSE %.5f\n", w, l / m, p / m }'
done
