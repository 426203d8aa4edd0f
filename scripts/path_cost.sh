#!/usr/bin/env bash
# GPU seconds and distance estimates per sample, phong against path mode at bounces 1, 3 and 5,
# on the seed's scene at SIZE x SIZE (default 512) with SAMPLES samples a pixel (default 8; path
# mode with the sun on along the seed's light direction): the four alternate, RUNS times each
# (default 9), medians of `--stats`' gpu_seconds. Usage: scripts/path_cost.sh [QJULIA] [RUNS] [SIZE] [SAMPLES]
set -euo pipefail
cd "$(dirname "$0")/.."
q=$(realpath "${1:-target/release/qjulia}")
runs=${2:-9} size=${3:-512} samples=${4:-8}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
configs=("phong" "path 1" "path 3" "path 5")
args() {
    case $1 in
        phong) echo "" ;;
        *) echo "--set shading.model=\"path\" --set sun.intensity=3 --set path.bounces=${1#path }" ;;
    esac
}
for ((k = 0; k < runs; k++)); do
    for c in "${configs[@]}"; do
        # shellcheck disable=SC2046
        "$q" render --width "$size" --height "$size" --set image.samples="$samples" $(args "$c") \
            -o "$tmp/x.png" --stats "$tmp/s.json" 2>/dev/null
        python3 -c "import json;d=json.load(open('$tmp/s.json'));print(d['gpu_seconds'] or d['render_seconds'], d['estimates_total'])" >>"$tmp/${c// /_}"
    done
done
echo "| model | gpu_seconds (median of $runs) | per sample | estimates per sample |"
echo "|---|---|---|---|"
for c in "${configs[@]}"; do
    python3 - "$tmp/${c// /_}" "$c" "$size" "$samples" <<'PY'
import statistics, sys
rows = [tuple(map(float, l.split())) for l in open(sys.argv[1])]
name, size, samples = sys.argv[2], int(sys.argv[3]), int(sys.argv[4])
t = statistics.median(r[0] for r in rows)
e = statistics.median(r[1] for r in rows)
print(f"| {name} | {t:.3f} | {t / samples * 1e3:.1f} ms | {e / (size * size * samples):.1f} |")
PY
done
