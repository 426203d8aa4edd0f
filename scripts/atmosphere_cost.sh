#!/usr/bin/env bash
# The atmosphere's cost (docs/book/atmosphere.md), A/B within one binary: each configuration
# alternates with the others, RUNS times each (default 9), medians of `--stats`' render_seconds
# (and gpu_seconds). Path mode on the path-traced preset at SIZE x SIZE (default 128) with its 64
# samples: no fog, fog (density 0.3, g 0.5), emission 1, and the built-in environment map; phong
# mode on the seed's look at 4 x SIZE square: none, fog (0.3), glow (strength 1), and the map as
# background and ambient light (ambient 0.3). Usage: scripts/atmosphere_cost.sh [QJULIA] [RUNS] [SIZE]
set -euo pipefail
cd "$(dirname "$0")/.."
q=$(realpath "${1:-target/release/qjulia}")
runs=${2:-9} size=${3:-128}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
path=(--preset path-traced --width "$size" --height "$size")
phong=(--width $((4 * size)) --height $((4 * size)))
configs=("path" "path+fog" "path+emission" "path+environment" "phong" "phong+fog" "phong+glow"
    "phong+environment")
args() {
    case $1 in
        path) echo "${path[*]}" ;;
        path+fog) echo "${path[*]} --set fog.density=0.3 --set fog.anisotropy=0.5" ;;
        path+emission) echo "${path[*]} --set material.emission=1" ;;
        path+environment) echo "${path[*]} --set environment.file=qjulia:dusk.hdr" ;;
        phong) echo "${phong[*]}" ;;
        phong+fog) echo "${phong[*]} --set fog.density=0.3" ;;
        phong+glow) echo "${phong[*]} --set glow.strength=1" ;;
        phong+environment) echo "${phong[*]} --set environment.file=qjulia:dusk.hdr \
            --set shading.environment_light=true --set shading.ambient=0.3" ;;
    esac
}
for ((k = 0; k < runs; k++)); do
    for c in "${configs[@]}"; do
        # shellcheck disable=SC2046
        "$q" render $(args "$c") -o "$tmp/x.png" --stats "$tmp/s.json" 2>/dev/null
        python3 -c "import json;d=json.load(open('$tmp/s.json'));print(d['render_seconds'], d['gpu_seconds'] or 0, d['estimates_total'])" >>"$tmp/${c//+/_}"
    done
done
echo "| configuration | render_seconds (median of $runs) | gpu_seconds | estimates_total |"
echo "|---|---|---|---|"
for c in "${configs[@]}"; do
    python3 - "$tmp/${c//+/_}" "$c" <<'PY'
import statistics, sys
rows = [[float(x) for x in line.split()] for line in open(sys.argv[1])]
med = lambda k: statistics.median(r[k] for r in rows)
print(f"| {sys.argv[2]} | {med(0):.4f} | {med(1):.4f} | {int(med(2)):,} |")
PY
done
