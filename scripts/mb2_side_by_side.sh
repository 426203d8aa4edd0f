#!/usr/bin/env bash
# Samples per second of path mode against Mandelbulber2 2.20's Monte Carlo mode on the seed's
# scene, side by side in one run: the two alternate, RUNS times each (default 9), and the medians
# are printed. MB2 renders benches/peers/mandelbulber/qjulia_mc64.fract (global illumination,
# 3 bounces, MC soft shadows, 64 samples; its Monte Carlo settings live in the file, since
# --override ignores them); qjulia renders the default scene in path mode with the same bounces
# and samples, the sun on along the seed's light direction. Both at SIZE x SIZE (default 128).
# Both clocks: MB2's whole process against qjulia's whole process, its render_seconds and its
# gpu_seconds.
# Usage: scripts/mb2_side_by_side.sh [QJULIA_BINARY] [RUNS] [SIZE]
set -euo pipefail
cd "$(dirname "$0")/.."
q=$(realpath "${1:-target/release/qjulia}")
runs=${2:-9}
size=${3:-128}
fract=$(realpath benches/peers/mandelbulber/qjulia_mc64.fract)
command -v mandelbulber2 >/dev/null || { echo "mandelbulber2 is not installed (apt-get install -y mandelbulber2)"; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mb=() qw=() qr=() qg=()
now() { date +%s.%N; }
for ((k = 0; k < runs; k++)); do
    t0=$(now)
    mandelbulber2 --nogui --format png --res "${size}x${size}" --output "$tmp/mb" "$fract" >/dev/null 2>&1
    t1=$(now)
    "$q" render --width "$size" --height "$size" --set 'shading.model="path"' --set sun.intensity=3 \
        --set path.bounces=3 --set image.samples=64 -o "$tmp/q.png" --stats "$tmp/q.json" 2>/dev/null
    t2=$(now)
    mb+=("$(echo "$t1 - $t0" | bc -l)")
    qw+=("$(echo "$t2 - $t1" | bc -l)")
    qr+=("$(python3 -c "import json;d=json.load(open('$tmp/q.json'));print(d['render_seconds'])")")
    qg+=("$(python3 -c "import json;d=json.load(open('$tmp/q.json'));print(d['gpu_seconds'] or d['render_seconds'])")")
done
median() { printf '%s\n' "$@" | sort -g | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR+1)/2] : (a[NR/2] + a[NR/2+1]) / 2}'; }
m=$(median "${mb[@]}") w=$(median "${qw[@]}") r=$(median "${qr[@]}") g=$(median "${qg[@]}")
samples=$((size * size * 64))
echo "runs: $runs each, alternating, ${size}x${size}, 64 samples, 3 bounces"
echo "Mandelbulber2 2.20 (whole process): median $m s, $(echo "$samples / $m" | bc -l | xargs printf '%.0f') samples/s"
echo "qjulia path mode (whole process):   median $w s, $(echo "$samples / $w" | bc -l | xargs printf '%.0f') samples/s ($(echo "$m / $w" | bc -l | xargs printf '%.1f')x)"
echo "qjulia path mode (render_seconds):  median $r s, $(echo "$samples / $r" | bc -l | xargs printf '%.0f') samples/s ($(echo "$m / $r" | bc -l | xargs printf '%.1f')x)"
echo "qjulia path mode (gpu_seconds):     median $g s, $(echo "$samples / $g" | bc -l | xargs printf '%.0f') samples/s ($(echo "$m / $g" | bc -l | xargs printf '%.1f')x)"
ls "$tmp"/mb* >/dev/null 2>&1 && cp "$(ls "$tmp"/mb* | head -1)" /tmp/mb2_side_by_side_mb2.png && cp "$tmp/q.png" /tmp/mb2_side_by_side_qjulia.png || true
