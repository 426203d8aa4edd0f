#!/usr/bin/env bash
# The parsers' coverage-guided fuzz (fuzz/, cargo-fuzz on nightly's libFuzzer).
#   scripts/fuzz.sh run SECONDS [TARGET...]   each target for SECONDS from its checked-in
#                                             corpus, one per core at a time
#                                             (QJULIA_FUZZ_JOBS); one summary line per target
#   scripts/fuzz.sh runs RUNS [TARGET...]     each target for RUNS executions instead
#   scripts/fuzz.sh grow RUNS [TARGET...]     each target for RUNS executions on fuzz/corpus/
#                                             itself, then minimise it: how the checked-in
#                                             corpus was grown
#   scripts/fuzz.sh seed                      rebuild fuzz/corpus/ from the repository's scenes
#                                             and files qjulia writes (needs target/release/qjulia),
#                                             then minimise it (cargo fuzz cmin)
# The limits, for every run: 10 s an input (a hang), 2048 MB resident, 256 MB a single
# allocation. A crash, hang or allocation past the limit leaves its input in
# fuzz/artifacts/TARGET/ and exits non-zero. New inputs found by a run go to a scratch copy of
# the corpus, not into fuzz/corpus/.
set -euo pipefail
cd "$(dirname "$0")/.."

TARGETS=(scene_toml set png_scene exr_scene animation mesh_box merge_part map_exr map_hdr)
LIMITS=(-timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=256)

fuzz() { (cd fuzz && cargo +nightly fuzz "$@"); }

seed() {
    local qjulia=target/release/qjulia scratch
    [ -x "$qjulia" ] || { echo "seed: build target/release/qjulia first" >&2; exit 2; }
    scratch=$(mktemp -d)
    trap 'rm -rf "$scratch"' RETURN
    rm -rf fuzz/corpus && mkdir -p "${TARGETS[@]/#/fuzz/corpus/}"
    # Scene text: the page's corpus (good and bad scenes), every preset, the whole default scene.
    cp web/test/corpus/*.toml fuzz/corpus/scene_toml/
    "$qjulia" schema --json | python3 -c '
import json, sys
for p in json.load(sys.stdin)["presets"]:
    if p["toml"]:
        open("fuzz/corpus/scene_toml/preset-" + p["slug"] + ".toml", "w").write(p["toml"])'
    "$qjulia" render --width 8 --height 8 -o "$scratch/default.png" 2>/dev/null
    "$qjulia" render --width 8 --height 8 --preset path-traced -o "$scratch/path.png" \
        --hdr "$scratch/path.exr" >/dev/null 2>&1 ||
        "$qjulia" render --width 8 --height 8 --set shading.model=\"path\" -o "$scratch/path.png" \
            --hdr "$scratch/path.exr" >/dev/null
    # An animation with keyframes, and the default demo's table.
    cat >fuzz/corpus/animation/keys.toml <<'TOML'
[animation]
frames = 24
fps = 12.0
path_radius = 0.1

[[animation.keys]]
frame = 0
"fractal.c" = [-0.2, 0.6, 0.2, 0.2]
"camera.eye" = [0.0, 0.0, -3.0]

[[animation.keys]]
frame = 23
"fractal.c" = [-0.4, 0.5, 0.1, 0.0]
"slice.x" = [1.0, 0.0, 0.0, 0.1]
TOML
    printf '[animation]\nframes = 3\n' >fuzz/corpus/animation/short.toml
    cp fuzz/corpus/scene_toml/preset-*.toml fuzz/corpus/animation/ 2>/dev/null || true
    # --set: NUL-separated arguments.
    printf 'fractal.c=[0.1, 0.2, 0.3, 0.4]\0image.width=64' >fuzz/corpus/set/two
    printf 'shading.model=path\0path.samples=4\0fractal.algebra="octonion"' >fuzz/corpus/set/path
    printf 'cut={normal=[0.0,1.0,0.0], offset=0.1}' >fuzz/corpus/set/table
    printf 'camera.eye=[0,0,-3]' >fuzz/corpus/set/eye
    # --box
    printf -- '-1.5,-1.5,-1.5,1.5,1.5,1.5' >fuzz/corpus/mesh_box/cube
    printf -- '0, 0 ,0,1e-3,2,3' >fuzz/corpus/mesh_box/spaces
    # Files qjulia writes: PNGs carry their scene, EXRs too; a partial EXR is a tile.
    cp "$scratch/default.png" "$scratch/path.png" fuzz/corpus/png_scene/
    cp "$scratch/path.exr" fuzz/corpus/exr_scene/
    "$qjulia" render --width 8 --height 8 --tile 0/2 --hdr "$scratch/part0.exr" 2>/dev/null
    "$qjulia" render --width 8 --height 8 --set shading.model=\"path\" --set image.samples=2 \
        --tile 1/2 --hdr "$scratch/part1.exr" 2>/dev/null
    cp "$scratch"/part*.exr fuzz/corpus/merge_part/
    cp "$scratch"/part*.exr fuzz/corpus/exr_scene/
    for target in "${TARGETS[@]}"; do
        mkdir -p "$scratch/min-$target"
        fuzz cmin -O "$target" "$PWD/fuzz/corpus/$target" -- "${LIMITS[@]}" >/dev/null 2>&1 || true
    done
    du -sh fuzz/corpus
}

# Runs every named target (all by default) with libFuzzer's LIMITS and $1 (-max_total_time=N
# or -runs=N) from a scratch copy of its corpus; prints "TARGET: N executions in S s, ..." each.
# The targets run QJULIA_FUZZ_JOBS at a time (default: one per core, `nproc`): libFuzzer runs
# one process on one core, so each target still gets its whole budget of a core to itself.
run() {
    local budget=$1 scratch status=0 jobs=${QJULIA_FUZZ_JOBS:-$(nproc)}
    shift
    local targets=("$@")
    [ "${#targets[@]}" -gt 0 ] || targets=("${TARGETS[@]}")
    # cargo fuzz builds one target, or all of them.
    if [ "$#" -eq 1 ]; then fuzz build -O "$1"; else fuzz build -O; fi
    scratch=$(mktemp -d)
    for target in "${targets[@]}"; do
        while [ "$(jobs -rp | wc -l)" -ge "$jobs" ]; do wait -n || true; done
        run_one "$budget" "$target" "$scratch" &
    done
    wait
    for target in "${targets[@]}"; do
        cat "$scratch/$target.summary"
        [ -e "$scratch/$target.failed" ] && status=1
    done
    rm -rf "$scratch"
    return "$status"
}

# One target of `run`: its summary in SCRATCH/TARGET.summary, SCRATCH/TARGET.failed on a
# finding.
run_one() {
    local budget=$1 target=$2 scratch=$3
    local log="$scratch/$target.log" summary="$scratch/$target.summary" start=$SECONDS
    cp -r "fuzz/corpus/$target" "$scratch/$target"
    : >"$summary"
    if ! fuzz run -O "$target" "$scratch/$target" -- "${LIMITS[@]}" "$budget" \
        -print_final_stats=1 >"$log" 2>&1; then
        touch "$scratch/$target.failed"
        echo "$target: FAILED (fuzz/artifacts/$target/):" >>"$summary"
        grep -E "ERROR|panicked|SUMMARY|Test unit written" "$log" | head -8 >>"$summary"
    fi
    local runs peak
    runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
    peak=$(sed -n 's/^stat::peak_rss_mb: *//p' "$log" | tail -1)
    printf '%s: %s executions in %d s, peak RSS %s MB, corpus %s -> %s inputs\n' \
        "$target" "${runs:-?}" "$((SECONDS - start))" "${peak:-?}" \
        "$(ls "fuzz/corpus/$target" | wc -l)" "$(ls "$scratch/$target" | wc -l)" >>"$summary"
}

# Runs every named target for $1 executions into its checked-in corpus, then minimises it.
grow() {
    local runs=$1 status=0
    shift
    local targets=("$@")
    [ "${#targets[@]}" -gt 0 ] || targets=("${TARGETS[@]}")
    fuzz build -O >/dev/null 2>&1
    for target in "${targets[@]}"; do
        local log start=$SECONDS
        log=$(mktemp)
        if ! fuzz run -O "$target" "$PWD/fuzz/corpus/$target" -- "${LIMITS[@]}" "-runs=$runs" \
            -print_final_stats=1 >"$log" 2>&1; then
            status=1
            echo "$target: FAILED (fuzz/artifacts/$target/):"
            grep -E "ERROR|panicked|SUMMARY|Test unit written" "$log" | head -8
        fi
        local done peak grown
        done=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
        peak=$(sed -n 's/^stat::peak_rss_mb: *//p' "$log" | tail -1)
        grown=$(ls "fuzz/corpus/$target" | wc -l)
        fuzz cmin -O "$target" "$PWD/fuzz/corpus/$target" -- "${LIMITS[@]}" >/dev/null 2>&1 || true
        printf '%s: %s executions in %d s, peak RSS %s MB, no finding: %s; corpus %s, minimised to %s\n' \
            "$target" "${done:-?}" "$((SECONDS - start))" "${peak:-?}" \
            "$([ "$status" = 0 ] && echo yes || echo NO)" "$grown" "$(ls "fuzz/corpus/$target" | wc -l)"
        rm -f "$log"
    done
    return "$status"
}

case "${1:-}" in
    run) shift; seconds=${1:?seconds}; shift; run "-max_total_time=$seconds" "$@" ;;
    runs) shift; runs=${1:?runs}; shift; run "-runs=$runs" "$@" ;;
    grow) shift; runs=${1:?runs}; shift; grow "$runs" "$@" ;;
    seed) seed ;;
    *) sed -n '2,16p' "$0" >&2; exit 2 ;;
esac
