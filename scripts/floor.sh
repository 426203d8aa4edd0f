#!/usr/bin/env bash
# The floor (issue 37, item 3): a render's quaternion iterations a second, and its share of
# this machine's peak for the same loop. The peak is measured, by the probe
# examples/iteration_peak.rs (the seed's iteration on every lane, none waiting for another; its
# best dispatch). The script also prints, for scale, the peak derived from the CPU's flags and
# clock: cores x clock x f32 lanes (256-bit vectors: lavapipe's width here) x 2 vector
# operations a cycle / 14 (the f32 operations of one quaternion iteration of iterate_orbit).
# The render runs RUNS times (default 9); the medians of gpu_seconds (or render_seconds where
# the adapter has no timestamps) and of render_seconds are used.
#   scripts/floor.sh BINARY render --preset seed --width 512 --height 512
#   RUNS=5 scripts/floor.sh target/release/qjulia render --preset path-traced --width 128 --height 128
set -euo pipefail
bin=$(realpath "$1")
shift
runs=${RUNS:-9}
cd "$(dirname "$0")/.."
probe=target/release/examples/iteration_peak
[[ -x $probe ]] || cargo build --release --locked --example iteration_peak >/dev/null
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$probe" >"$tmp/probe"
for _ in $(seq "$runs"); do
    "$bin" "$@" -o "$tmp/out.png" --stats "$tmp/s.json" >/dev/null 2>&1
    python3 -c "import json;d=json.load(open('$tmp/s.json'));print(d['gpu_seconds'] or d['render_seconds'], d['render_seconds'], d['iterations_total'], d['estimates_total'], d['samples_total'])" >>"$tmp/runs"
done
python3 - "$tmp/runs" "$tmp/probe" <<'PY'
import os, re, statistics, sys
rows = [list(map(float, line.split())) for line in open(sys.argv[1])]
probe = dict(line.split(None, 1) for line in open(sys.argv[2]))
peak = float(probe["peak_iterations_per_second"])
gpu = statistics.median(r[0] for r in rows)
render = statistics.median(r[1] for r in rows)
iterations, estimates, samples = rows[0][2], rows[0][3], rows[0][4]
cpuinfo = open("/proc/cpuinfo").read()
mhz = float(re.search(r"cpu MHz\s*:\s*([\d.]+)", cpuinfo).group(1))
cores = os.cpu_count()
derived = cores * mhz * 1e6 * 8 * 2 / 14
print(f"adapter: {probe['adapter'].strip()}")
print(f"render: {len(rows)} runs; iterations_total {iterations:.0f} "
      f"({iterations / estimates:.2f} an estimate, {iterations / samples:.1f} a sample)")
print(f"peak, measured by the probe: {peak / 1e9:.3f} G iterations/s")
print(f"peak, derived ({cores} cores x {mhz:.0f} MHz x 8 lanes x 2 / 14): {derived / 1e9:.3f} G iterations/s")
for name, seconds in (("gpu_seconds", gpu), ("render_seconds", render)):
    rate = iterations / seconds
    print(f"{name} median {seconds:.4f} s: {rate / 1e9:.3f} G iterations/s, "
          f"{100 * rate / peak:.1f}% of the measured peak, {100 * rate / derived:.1f}% of the derived")
PY
