#!/usr/bin/env bash
# A/B timing of two qjulia binaries on one command: old and new alternating, RUNS runs each
# (default 9), medians of the whole process's wall time and of its stats: render_seconds and
# gpu_seconds for `render`, frames_per_second and render_seconds for `animate`.
#   scripts/ab.sh OLD_BINARY NEW_BINARY render --preset seed --width 3840 --height 2160
#   scripts/ab.sh OLD_BINARY NEW_BINARY animate --preset seed --width 512 --height 512 --frames 0..29
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
        case $1 in
            animate) out=(--out "$tmp/$which-frames") ;;
            *) out=(-o "$tmp/$which.png") ;;
        esac
        rm -rf "$tmp/$which-frames"
        start=$(date +%s.%N)
        "$bin" "$@" "${out[@]}" --stats "$tmp/$which.json" 2>/dev/null
        end=$(date +%s.%N)
        python3 -c "
import json
d = json.load(open('$tmp/$which.json'))
a = d.get('frames_per_second', d.get('gpu_seconds') or 0)
print('$which', $end - $start, d['render_seconds'], a)" >>"$tmp/times"
    done
done
third=gpu_seconds
[[ $1 == animate ]] && third=frames_per_second
python3 - "$tmp/times" "$third" <<'PY'
import statistics, sys
rows = [line.split() for line in open(sys.argv[1])]
for which in ("old", "new"):
    cols = [[float(r[k]) for r in rows if r[0] == which] for k in (1, 2, 3)]
    print(f"{which}: {len(cols[0])} runs, medians: wall {statistics.median(cols[0]):.3f} s, "
          f"render_seconds {statistics.median(cols[1]):.4f}, {sys.argv[2]} {statistics.median(cols[2]):.4f}")
PY
