#!/usr/bin/env bash
# A/B timing of two qjulia binaries on one render: old and new alternating, RUNS runs each
# (default 9), medians of the whole process's wall time, render_seconds and gpu_seconds.
#   scripts/ab.sh OLD_BINARY NEW_BINARY render --preset seed --width 3840 --height 2160
set -euo pipefail
old=$1 new=$2
shift 2
runs=${RUNS:-9}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for _ in $(seq "$runs"); do
    for which in old new; do
        bin=$old
        [[ $which == new ]] && bin=$new
        start=$(date +%s.%N)
        "$bin" "$@" -o "$tmp/$which.png" --stats "$tmp/$which.json" 2>/dev/null
        end=$(date +%s.%N)
        python3 -c "import json; d = json.load(open('$tmp/$which.json')); print('$which', $end - $start, d['render_seconds'], d['gpu_seconds'] or 0)" >>"$tmp/times"
    done
done
python3 - "$tmp/times" <<'PY'
import statistics, sys
rows = [line.split() for line in open(sys.argv[1])]
for which in ("old", "new"):
    cols = [[float(r[k]) for r in rows if r[0] == which] for k in (1, 2, 3)]
    print(f"{which}: {len(cols[0])} runs, medians: wall {statistics.median(cols[0]):.3f} s, "
          f"render_seconds {statistics.median(cols[1]):.3f}, gpu_seconds {statistics.median(cols[2]):.3f}")
PY
