#!/bin/bash
# Adaptive sampling's efficiency (issue 49, item 1): the mean squared error over seeds times the
# mean samples a pixel took (lower is better), for plain Sobol' sampling, the adaptive rule of
# binary OLD and that of binary NEW, on three scenes: the path-traced preset, the path-gallery
# preset and a smooth Lambert one (the unit ball, path traced, no specular lobe).
#
#     scripts/adaptive_efficiency.sh OLD NEW [SIZE] [SEEDS] [REF] [TARGET]
#
# Each render is SIZE x SIZE (default 64). The reference is the mean of two renders of REF
# (default 4096) samples of the `random` sampler with seeds of their own; its own error is taken
# out of each MSE (examples/adaptive_study.rs, `mse`). Each rule renders SEEDS seeds (default 12,
# `path.seed` 1..SEEDS): plain at 64 samples, adaptive at most 256 with `path.noise_target`
# TARGET (default 0.05) and `path.min_samples` 16. Prints, per scene and rule, the mean samples a
# pixel, the MSE (mean over seeds, with its standard error) and their product, and the product's
# ratio to OLD's. QJULIA_EFFICIENCY_SCENES=NAME[,NAME...] runs only those scenes. Needs the example
# built: cargo build --release --example adaptive_study.
set -eu
cd "$(dirname "$0")/.."
[ $# -ge 2 ] || { echo "usage: $0 OLD NEW [SIZE] [SEEDS] [REF] [TARGET]"; exit 2; }
OLD=$1
NEW=$2
SIZE=${3:-64}
SEEDS=${4:-12}
REF=${5:-4096}
TARGET=${6:-0.05}
# shellcheck source=scripts/mse_common.sh
. scripts/mse_common.sh
samples_of() { # a stats file: the samples a pixel took, on average
    python3 -c "import json, sys; print(json.load(open(sys.argv[1]))['samples_total'] / $SIZE / $SIZE)" "$1"
}
for entry in "${scenes[@]}"; do
    name=${entry%%|*}
    args=${entry#*|}
    case ",${QJULIA_EFFICIENCY_SCENES:-$name}," in *",$name,"*) ;; *) continue ;; esac
    references "$name" "$args"
    runs=()
    for seed in $(seq "$SEEDS"); do
        render "$NEW" "$WORK/$name-plain-$seed" "$args" --set image.samples=64 --set path.seed="$seed"
        for rule in old new; do
            bin=$OLD
            [ "$rule" = new ] && bin=$NEW
            render "$bin" "$WORK/$name-$rule-$seed" "$args" --set image.samples=256 \
                --set path.noise_target="$TARGET" --set path.min_samples=16 --set path.seed="$seed"
        done
        runs+=("$WORK/$name-plain-$seed.exr" "$WORK/$name-old-$seed.exr" "$WORK/$name-new-$seed.exr")
    done
    "$STUDY" mse "$WORK/$name-ref-a.exr" "$WORK/$name-ref-b.exr" "${runs[@]}" >"$WORK/$name.mse"
    echo "$name (${SIZE}x${SIZE}, $SEEDS seeds, reference $(head -1 "$WORK/$name.mse" | sed 's/.*: //')):"
    OLD_PRODUCT=""
    for rule in old new plain; do
        for seed in $(seq "$SEEDS"); do
            mse=$(grep "$name-$rule-$seed.exr" "$WORK/$name.mse" | cut -d' ' -f2)
            echo "$mse $(samples_of "$WORK/$name-$rule-$seed.json")"
        done >"$WORK/$name-$rule.rows"
        read -r SPP MSE SE PRODUCT < <(awk '{m += $1; q += $1 * $1; s += $2; n++}
            END {mean = m / n; se = sqrt((q / n - mean * mean) / (n - 1)); spp = s / n
                 printf "%.2f %.4e %.1e %.4e\n", spp, mean, se, mean * spp}' "$WORK/$name-$rule.rows")
        [ "$rule" = old ] && OLD_PRODUCT=$PRODUCT
        RATIO=""
        [ -n "$OLD_PRODUCT" ] && RATIO=$(awk -v a="$OLD_PRODUCT" -v b="$PRODUCT" 'BEGIN {printf ", old rule / this %.2fx", a / b}')
        echo "  $rule: $SPP samples a pixel, mse $MSE +- $SE, mse x samples $PRODUCT$RATIO"
    done
done
