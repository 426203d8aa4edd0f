#!/usr/bin/env bash
# Error against run time of a path-mode render, measured across seeds: renders the same scene
# with path.seed = 1..SEEDS (each seed draws independently scrambled points), and prints the mean
# over pixels of the variance of a pixel's luminance across the seeds, the median render_seconds,
# and their product (lower is better: the time to a given noise scales with it).
#   scripts/seed_variance.sh BINARY SEEDS render --width 128 --height 128 --set 'shading.model="path"' ...
# Needs python3 with numpy and OpenEXR (`pip install numpy OpenEXR`).
set -euo pipefail
bin=$1 seeds=$2
shift 2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for seed in $(seq "$seeds"); do
    "$bin" "$@" --set "path.seed=$seed" -o "$tmp/out.png" --hdr "$tmp/$seed.exr" \
        --stats "$tmp/$seed.json" 2>/dev/null
done
python3 - "$tmp" "$seeds" <<'PY'
import json, statistics, sys
import numpy as np
import OpenEXR
tmp, seeds = sys.argv[1], int(sys.argv[2])
lum, times = [], []
for k in range(1, seeds + 1):
    rgb = np.asarray(OpenEXR.File(f"{tmp}/{k}.exr").channels()["RGB"].pixels, dtype=np.float64)
    lum.append(0.2126 * rgb[..., 0] + 0.7152 * rgb[..., 1] + 0.0722 * rgb[..., 2])
    times.append(json.load(open(f"{tmp}/{k}.json"))["render_seconds"])
variance = np.array(lum).var(axis=0, ddof=1).mean()
t = statistics.median(times)
print(f"{seeds} seeds: mean pixel variance {variance:.4e}, median render_seconds {t:.4f}, "
      f"variance x time {variance * t:.4e}, image mean {np.mean(lum):.5f}")
PY
