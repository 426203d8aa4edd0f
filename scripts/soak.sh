#!/bin/bash
# The explorer's soak (issue 22): `qjulia explore` under Xvfb on the GPU (lavapipe where there is
# no other), driven for SECONDS (default 600) by random input through xdotool: drags (orbit,
# pan), the wheel, keys (arrows, + and -, R, M for 2D/3D, Space to play c), preset switches,
# timeline scrubs and window resizes. Every 2 s it samples the explorer's resident memory.
#
#     scripts/soak.sh [SECONDS] [SEED] [--timing | --memory-reported]
#
# The checks, each printed with its figure:
#   - no panic in the explorer's log, and its window alive at the end;
#   - resident memory settled at the end grows by at most 50 MB over its level after the first
#     minute (or the first sixth, in a short soak), and 60 MB more for each pipeline built after
#     it (the memory block below gives the arithmetic); no kernel holds over 16 pipelines;
#   - with --timing only (the explorer's per-frame log, QJULIA_EXPLORE_LOG=frames), over the
#     timed part: the 95th percentile of the frames' own work is within 2x of its median, and
#     (issue 48) no frame's own work is over 250 ms (the tour's preset switches included), the
#     95th percentile of the interval between frames is at most 50 ms, and the 95th percentile
#     of the input latency is at most 100 ms. The input latency of a drag's mouse move is the
#     time from its sending (bash's EPOCHREALTIME) to the end of the first frame that shows a
#     render begun after the first frame that took the move (the log's `at`, `shows` and
#     `input`). CI runs a 60 s soak without --timing: on a shared machine, timing is no test.
# --memory-reported prints the memory figures without failing on them: CI's 60 s soak, too short
# to tell a leak from the working set (tests/render/repeated_renders.rs holds the leak the soak found;
# docs/book/robustness.md, "The explorer, soaked").
# QJULIA_SOAK_ONLY=drag (or wheel, key, preset, scrub, resize) repeats that one action, to find
# which one a figure comes from. QJULIA_SOAK_KEEP=FILE keeps the explorer's log in FILE, the
# memory samples (seconds, kB) in FILE.rss and the actions (seconds, action) in FILE.actions.
# Before the timed part, a tour visits every preset in 3D and 2D (QJULIA_SOAK_TOUR=0: none);
# QJULIA_SOAK_PRESET=K then chooses the menu's preset K (0-based; 15 is "Path traced") for the
# timed part to start in.
# Exit 0 when every check passes, 1 when one fails, 2 when the soak cannot start.
# Needs Xvfb and xdotool (Debian: xvfb, xdotool); the binary is target/release/qjulia (QJULIA).
set -u
cd "$(dirname "$0")/.."
SECONDS_TOTAL=${1:-600}
SEED=${2:-22}
TIMING=0
MEMORY_CHECKED=1
case "${3:-}" in
    --timing) TIMING=1 ;;
    --memory-reported) MEMORY_CHECKED=0 ;;
    "") ;;
    *) echo "soak: unknown option ${3}"; exit 2 ;;
esac
QJULIA=${QJULIA:-target/release/qjulia}
for tool in Xvfb xdotool; do
    command -v "$tool" >/dev/null || { echo "soak: $tool is missing (apt-get install xvfb xdotool)"; exit 2; }
done
[ -x "$QJULIA" ] || { echo "soak: $QJULIA is missing (cargo build --release)"; exit 2; }

WORK=$(mktemp -d)
DISPLAY_NUM=:$((90 + RANDOM % 9))
Xvfb "$DISPLAY_NUM" -screen 0 1600x1000x24 -nolisten tcp >"$WORK/xvfb.log" 2>&1 &
XVFB=$!
cleanup() {
    [ -n "${APP:-}" ] && kill "$APP" 2>/dev/null
    kill "$XVFB" 2>/dev/null
    wait 2>/dev/null
    if [ -n "${QJULIA_SOAK_KEEP:-}" ]; then
        cp "$WORK/explore.log" "$QJULIA_SOAK_KEEP"
        cp "$WORK/rss" "$QJULIA_SOAK_KEEP.rss" 2>/dev/null
        cp "$WORK/actions" "$QJULIA_SOAK_KEEP.actions" 2>/dev/null
        cp "$WORK/inputs" "$QJULIA_SOAK_KEEP.inputs" 2>/dev/null
    fi
    rm -rf "$WORK"
}
trap cleanup EXIT
export DISPLAY=$DISPLAY_NUM
sleep 1
mkdir -p "$WORK/home" "$WORK/xdg"
chmod 700 "$WORK/xdg"
# A fresh home: no saved window or scene from an earlier run.
HOME="$WORK/home" XDG_RUNTIME_DIR="$WORK/xdg" QJULIA_EXPLORE_LOG=frames \
    "$QJULIA" explore >"$WORK/explore.log" 2>&1 &
APP=$!
WIN=""
for _ in $(seq 60); do
    WIN=$(xdotool search --pid "$APP" 2>/dev/null | tail -1)
    [ -n "$WIN" ] && break
    sleep 1
done
[ -n "$WIN" ] || { echo "soak: the explorer's window never showed"; cat "$WORK/explore.log"; exit 2; }
xdotool windowsize "$WIN" 1280 800
sleep 3

RANDOM=$SEED
rss() { awk '/^VmRSS/ {print $2}' "/proc/$APP/status" 2>/dev/null; }
geometry() {
    eval "$(xdotool getwindowgeometry --shell "$WIN")"
    W=$WIDTH
    H=$HEIGHT
}
# A point in the view: right of the control panel (345 pixels), below the menu bar, above the
# timeline and the status line.
view_point() {
    X=$((360 + RANDOM % (W - 380)))
    Y=$((40 + RANDOM % (H - 160)))
}
drag() {
    local button=${1:-1}
    view_point
    xdotool mousemove --window "$WIN" "$X" "$Y" mousedown "$button"
    for _ in $(seq $((3 + RANDOM % 6))); do
        X=$((X + RANDOM % 61 - 30))
        Y=$((Y + RANDOM % 61 - 30))
        sleep 0.05
        # When the move was sent, in milliseconds since the epoch: the input latency's start.
        local us=${EPOCHREALTIME/./}
        echo "$((us / 1000)).$((us / 100 % 10))" >>"$WORK/inputs"
        xdotool mousemove --window "$WIN" "$X" "$Y"
    done
    sleep 0.05
    xdotool mouseup "$button"
}
wheel() {
    view_point
    xdotool mousemove --window "$WIN" "$X" "$Y"
    for _ in $(seq $((1 + RANDOM % 4))); do xdotool click $((4 + RANDOM % 2)); done
}
keys=(Left Right Up Down plus minus r m space)
key() {
    xdotool windowfocus "$WIN" 2>/dev/null
    DETAIL=${keys[RANDOM % ${#keys[@]}]}
    xdotool key --window "$WIN" "$DETAIL"
}
# The Presets menu of the menu bar, and its entry K of PRESETS (23 pixels apart); preset: one at
# random.
PRESETS=17
preset_number() {
    xdotool mousemove --window "$WIN" 62 12 click 1
    sleep 0.3
    xdotool mousemove --window "$WIN" 95 $((39 + 23 * $1)) click 1
}
preset() {
    DETAIL=$((RANDOM % PRESETS))
    preset_number "$DETAIL"
}
# The timeline's strip: the band above the status line, the window's width.
scrub() {
    local y=$((H - 45))
    X=$((20 + RANDOM % (W - 40)))
    xdotool mousemove --window "$WIN" "$X" "$y" mousedown 1
    for _ in $(seq 4); do
        X=$((20 + RANDOM % (W - 40)))
        sleep 0.05
        xdotool mousemove --window "$WIN" "$X" "$y"
    done
    xdotool mouseup 1
}
resize() {
    DETAIL="$((900 + RANDOM % 600)) $((600 + RANDOM % 350))"
    xdotool windowsize "$WIN" $DETAIL
}

# The tour, before the timed part: every preset once, in 3D and in 2D, so that the scenes'
# pipelines (a few MB each on lavapipe, and bounded: a kernel holds at most 16) are built
# before memory is measured, and a growth after the first minute is a leak rather than a
# preset the random walk met late. QJULIA_SOAK_TOUR=0 leaves it out.
if [ "${QJULIA_SOAK_TOUR:-1}" != 0 ]; then
    for k in $(seq 0 $((PRESETS - 1))); do
        preset_number "$k"
        sleep 2
        xdotool windowfocus "$WIN" 2>/dev/null
        xdotool key --window "$WIN" m
        sleep 2
        xdotool key --window "$WIN" m
        sleep 1
    done
    echo "soak: toured the $PRESETS presets in 3D and 2D, resident $(rss) kB"
fi
if [ -n "${QJULIA_SOAK_PRESET:-}" ]; then
    preset_number "$QJULIA_SOAK_PRESET"
    sleep 1
fi

START=$(date +%s)
START_MS=$(awk -v s="$START" 'BEGIN {printf "%.1f", s * 1000}')
MINUTE=$(( SECONDS_TOTAL / 6 < 60 ? SECONDS_TOTAL / 6 : 60 ))
RSS_BASE=""
RSS_MAX=0
ACTIONS=0
LAST_SAMPLE=0
while :; do
    NOW=$(date +%s)
    ELAPSED=$((NOW - START))
    [ "$ELAPSED" -ge "$SECONDS_TOTAL" ] && break
    kill -0 "$APP" 2>/dev/null || break
    geometry
    if [ -n "${QJULIA_SOAK_ONLY:-}" ]; then
        ACTION=$QJULIA_SOAK_ONLY
    else case $((RANDOM % 10)) in
        0 | 1 | 2) ACTION="drag 1" ;;
        3) ACTION="drag 3" ;;
        4) ACTION=wheel ;;
        5 | 6) ACTION=key ;;
        7) ACTION=preset ;;
        8) ACTION=scrub ;;
        9) [ $((RANDOM % 3)) = 0 ] && ACTION=resize || ACTION=key ;;
    esac; fi
    DETAIL=""
    $ACTION
    echo "$ELAPSED $ACTION $DETAIL" >>"$WORK/actions"
    ACTIONS=$((ACTIONS + 1))
    sleep 0.$((1 + RANDOM % 4))
    if [ $((NOW - LAST_SAMPLE)) -ge 2 ]; then
        LAST_SAMPLE=$NOW
        R=$(rss)
        [ -z "$R" ] && continue
        if [ "$ELAPSED" -ge "$MINUTE" ]; then
            [ -z "$RSS_BASE" ] && RSS_BASE=$R
            [ "$R" -gt "$RSS_MAX" ] && RSS_MAX=$R
        fi
        echo "$ELAPSED $R $NOW" >>"$WORK/rss"
    fi
done

FAIL=0
if kill -0 "$APP" 2>/dev/null && xdotool getwindowname "$WIN" >/dev/null 2>&1; then
    echo "soak: alive after ${ELAPSED} s and $ACTIONS random actions: yes"
else
    echo "soak: alive after ${ELAPSED} s and $ACTIONS random actions: NO"
    FAIL=1
fi
PANICS=$(grep -c "panicked" "$WORK/explore.log")
echo "soak: panics: $PANICS"
[ "$PANICS" = 0 ] || { FAIL=1; grep -m3 -A3 panicked "$WORK/explore.log"; }
# Memory (docs/book/robustness.md, "The explorer without a GPU"): the settled level after the
# first minute (the median of the samples in the WINDOW seconds from it) against the settled level
# at the end (the median of the last WINDOW seconds), so that a transient working set (a large
# window's buffers, given back) is not a leak. What the explorer keeps for good is its kernels'
# pipelines, at most MAX_PIPELINES (16) a kernel and each up to PIPELINE_MB on lavapipe (the
# largest step of resident memory at one pipeline's build in the soaks measured), so the limit is
# 50 MB and PIPELINE_MB for each pipeline built after the first minute (the view thread's log:
# `explore view pipelines held`).
PIPELINE_MB=60
WINDOW=$(( MINUTE < 30 ? MINUTE : 30 ))
if [ -n "$RSS_BASE" ]; then
    median_kb() { # the median of the rss samples whose elapsed seconds lie in [$1, $2)
        awk -v a="$1" -v b="$2" '$1 >= a && $1 < b {print $2}' "$WORK/rss" | sort -g |
            awk '{v[NR] = $1} END {print (NR ? v[int((NR + 1) / 2)] : 0)}'
    }
    SETTLED_BASE=$(median_kb "$MINUTE" $((MINUTE + WINDOW)))
    SETTLED_END=$(median_kb $((ELAPSED - WINDOW)) $((ELAPSED + 1)))
    SETTLED=$(( (SETTLED_END - SETTLED_BASE) / 1024 ))
    # The pipelines held (their sum over the kernels) at each change, after the first minute:
    # how many were built; and the most any one kernel held.
    grep "^explore view pipelines held" "$WORK/explore.log" |
        sed 's/^explore view pipelines held: \(.*\); resident .*; at \([0-9.]*\)$/\2 \1/' >"$WORK/pipelines"
    BUILT=$(awk -v t=$(( (START + MINUTE) * 1000 )) '{n = 0; for (i = 3; i <= NF; i += 2) n += $i + 0}
        $1 >= t && n > last {built += n - last} {last = n} END {print built + 0}' "$WORK/pipelines")
    MOST_HELD=$(awk '{for (i = 3; i <= NF; i += 2) if ($i + 0 > m) m = $i + 0} END {print m + 0}' "$WORK/pipelines")
    LIMIT=$(( 50 + PIPELINE_MB * BUILT ))
    FIRST=$(head -1 "$WORK/rss" | cut -d' ' -f2)
    echo "soak: resident memory ${FIRST} kB at the start, ${RSS_BASE} kB after ${MINUTE} s, at most ${RSS_MAX} kB after (peak $(( (RSS_MAX - RSS_BASE) / 1024 )) MB over it)"
    echo "soak: pipelines built after ${MINUTE} s: ${BUILT}; the most one kernel held: ${MOST_HELD} (at most 16)"
    VERDICT="reported, not checked"
    if [ "$MEMORY_CHECKED" = 1 ]; then
        VERDICT="limit ${LIMIT} MB: 50 + ${PIPELINE_MB} x ${BUILT} pipelines"
        [ "$SETTLED" -le "$LIMIT" ] || { FAIL=1; VERDICT="$VERDICT: NO"; }
        [ "$MOST_HELD" -le 16 ] || { FAIL=1; VERDICT="$VERDICT; a kernel held ${MOST_HELD} pipelines: NO"; }
    fi
    echo "soak: settled memory ${SETTLED_BASE} kB from ${MINUTE} s, ${SETTLED_END} kB at the end (medians over ${WINDOW} s): growth ${SETTLED} MB (${VERDICT})"
else
    echo "soak: no memory sample after ${MINUTE} s"
    FAIL=1
fi
FRAMES=$(grep -c "^explore frame" "$WORK/explore.log")
# The frames' own work (ms), sorted: median and 95th percentile.
grep "^explore frame" "$WORK/explore.log" | sed 's/.*: \([0-9.]*\) ms work.*/\1/' | sort -g >"$WORK/work"
if [ "$FRAMES" -gt 0 ]; then
    MEDIAN=$(awk -v n="$FRAMES" 'NR == int((n + 1) / 2) {print; exit}' "$WORK/work")
    P95=$(awk -v n="$FRAMES" 'NR == int(n * 0.95 + 0.999) {print; exit}' "$WORK/work")
    MAX=$(tail -1 "$WORK/work")
    echo "soak: $FRAMES frames; their own work: median $MEDIAN ms, 95th percentile $P95 ms, max $MAX ms"
    # The timed part's frames: the interval between them, and the input latency of the drags'
    # moves (see the header).
    grep "^explore frame" "$WORK/explore.log" |
        sed -n 's/.*: \([0-9.]*\) ms work, \([0-9.]*\) ms since the last, at \([0-9.]*\), shows \([-0-9.]*\)\(, input\)\{0,1\}.*/\1 \2 \3 \4 \5/p' |
        awk -v s="$START_MS" '$3 >= s' >"$WORK/timed"
    percentiles() { # a sorted file: its median, 95th percentile and maximum
        awk '{v[NR] = $1} END {if (NR == 0) {print "- - -"; exit}
            printf "%s %s %s\n", v[int((NR + 1) / 2)], v[int(NR * 0.95 + 0.999)], v[NR]}' "$1"
    }
    awk 'NR > 1 {print $2}' "$WORK/timed" | sort -g >"$WORK/intervals"
    read -r I50 I95 IMAX < <(percentiles "$WORK/intervals")
    echo "soak: the timed part's $(wc -l <"$WORK/intervals") frame intervals: median $I50 ms, 95th percentile $I95 ms, max $IMAX ms"
    touch "$WORK/inputs"
    awk 'NR == FNR {at[NR] = $3; end[NR] = $3 + $1; shows[NR] = $4; input[NR] = ($5 != ""); n = NR; next}
        {t = $1; i = 1; while (i <= n && !(input[i] && at[i] >= t)) i++
         if (i > n) next
         h = at[i]; j = i; while (j <= n && !(shows[j] != "-" && shows[j] + 0 >= h)) j++
         if (j <= n) printf "%.1f\n", end[j] - t}' "$WORK/timed" "$WORK/inputs" | sort -g >"$WORK/latency"
    read -r L50 L95 LMAX < <(percentiles "$WORK/latency")
    echo "soak: input latency of $(wc -l <"$WORK/latency") of $(wc -l <"$WORK/inputs") drag moves: median $L50 ms, 95th percentile $L95 ms, max $LMAX ms"
    if [ "$TIMING" = 1 ]; then
        if awk -v m="$MEDIAN" -v p="$P95" 'BEGIN {exit !(p <= 2 * m)}'; then
            echo "soak: 95th percentile within 2x of the median: yes"
        else
            echo "soak: 95th percentile within 2x of the median: NO"
            FAIL=1
        fi
        check() { # name, figure, limit
            if awk -v v="$2" -v l="$3" 'BEGIN {exit !(v != "-" && v <= l)}'; then
                echo "soak: $1 $2 ms, at most $3 ms: yes"
            else
                echo "soak: $1 $2 ms, at most $3 ms: NO"
                FAIL=1
            fi
        }
        check "longest frame's own work" "$MAX" 250
        check "frame interval's 95th percentile" "$I95" 50
        check "input latency's 95th percentile" "$L95" 100
    fi
else
    echo "soak: no frame logged"
    FAIL=1
fi
[ "$FAIL" = 0 ] && echo "soak: passed" || echo "soak: FAILED"
exit "$FAIL"
