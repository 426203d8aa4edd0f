#!/usr/bin/env bash
# Byte identity of two qjulia binaries' outputs: every output of render (GPU, CPU f32 and CPU
# f64; PNG, depth and steps), the step views, render2d, animate frames and mesh PLY/STL/OBJ, on
# a few presets at small sizes. Prints a markdown table, one row per output, and exits 1 when
# any output differs. For a refactor that must change no byte:
#   scripts/identity.sh OLD_BINARY NEW_BINARY
set -uo pipefail
old=$(realpath "$1") new=$(realpath "$2")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
size=(--width 96 --height 72)
differ=0
echo "| command | outputs | identical |"
echo "|---|---|---|"
# Runs one command with each binary in its own folder; compares every file it wrote.
check() {
    local label=$1
    shift
    for which in old new; do
        local bin=$old
        [[ $which == new ]] && bin=$new
        rm -rf "$tmp/$which" && mkdir -p "$tmp/$which"
        (cd "$tmp/$which" && "$bin" "$@" >/dev/null 2>"$tmp/$which.err") || {
            echo "| \`$label\` | $which failed: $(tail -1 "$tmp/$which.err") | no |"
            differ=1
            return
        }
    done
    local files verdict=yes
    files=$(cd "$tmp/old" && find . -type f | sort)
    if [[ "$files" != "$(cd "$tmp/new" && find . -type f | sort)" ]]; then
        verdict="no (different files)"
    else
        for f in $files; do
            cmp -s "$tmp/old/$f" "$tmp/new/$f" || verdict="no ($f)"
        done
    fi
    [[ $verdict == yes ]] || differ=1
    echo "| \`$label\` | $(echo "$files" | sed 's|^\./||' | paste -sd' ') | $verdict |"
}
for preset in seed gallery deep-zoom; do
    for backend in "gpu f32" "cpu f32" "cpu f64" "gpu f64"; do
        set -- $backend
        args=(render --preset "$preset" "${size[@]}" --backend "$1" --precision "$2")
        check "${args[*]}" "${args[@]}" -o p.png --depth d.npy --steps s.npy
    done
    check "render --preset $preset (auto)" render --preset "$preset" "${size[@]}" -o p.png --depth d.npy
    for backend in gpu cpu; do
        check "render --preset $preset --backend $backend --depth only" \
            render --preset "$preset" "${size[@]}" --backend "$backend" --depth d.npy --steps s.npy
        for view in steps divergence; do
            check "render --preset $preset --backend $backend --view $view" \
                render --preset "$preset" "${size[@]}" --backend "$backend" --view "$view" -o v.png
        done
    done
done
for preset in seed deep-zoom-2d; do
    for backend in "gpu auto" "cpu f32" "cpu f64"; do
        set -- $backend
        check "render2d --preset $preset --backend $1 --precision $2" \
            render2d --preset "$preset" "${size[@]}" --backend "$1" --precision "$2" -o p.png
    done
done
for backend in gpu cpu; do
    check "animate --frames 0..3 --backend $backend" animate "${size[@]}" --frames 0..3 --out f --backend "$backend"
    check "animate deep (auto) --backend $backend" animate --preset deep-zoom "${size[@]}" --frames 0..1 --out f --backend "$backend"
done
for ext in ply stl obj; do
    for backend in gpu "cpu --precision f64"; do
        check "mesh --resolution 48 --backend $backend -o m.$ext" mesh --resolution 48 --backend $backend -o "m.$ext"
    done
done
exit $differ
