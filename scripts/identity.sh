#!/usr/bin/env bash
# Byte identity of two qjulia binaries' outputs: every output of render (GPU, CPU f32 and CPU
# f64; PNG, depth and steps), the step views, render2d, animate frames and mesh PLY/STL/OBJ, path
# mode, the denoiser, adaptive sampling, --hdr, tiles and merge, `schema --json` and `gpu-params
# --json`, on a few presets at small sizes (PNGs and EXRs without their embedded scene text, see
# `same`). Prints a markdown table, one row per output, and exits 1 when
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
# Two files the same: byte for byte, except that PNGs are compared without their embedded scene
# (the `qjulia-scene` iTXt chunk, which names every key, so a new key changes it): every other
# chunk (the header, the pixels' IDAT) byte for byte. Needs python3 for PNGs.
same() {
    if [[ $1 == *.png ]]; then
        python3 - "$1" "$2" <<'PY'
import struct, sys
def chunks(path):
    data = open(path, "rb").read()
    out, at = [], 8
    while at < len(data):
        (n,) = struct.unpack(">I", data[at:at + 4])
        kind, body = data[at + 4:at + 8], data[at + 8:at + 8 + n]
        if not (kind == b"iTXt" and body.startswith(b"qjulia-scene\0")):
            out.append((kind, body))
        at += 12 + n
    return data[:8], out
sys.exit(0 if chunks(sys.argv[1]) == chunks(sys.argv[2]) else 1)
PY
    elif [[ $1 == *.exr ]] && ! cmp -s "$1" "$2"; then
        # An EXR holds the scene in its `qjulia-scene` header attribute (a new key changes
        # it): every channel's samples and every other attribute must be the same. Needs
        # python3 with the OpenEXR and numpy modules.
        python3 - "$1" "$2" <<'PY'
import sys
import numpy as np
import OpenEXR
def read(path):
    f = OpenEXR.File(path)
    parts = []
    for part in f.parts:
        header = {k: v for k, v in part.header.items() if k != "qjulia-scene"}
        channels = {k: np.asarray(v.pixels) for k, v in part.channels.items()}
        parts.append((header, channels))
    return parts
a, b = read(sys.argv[1]), read(sys.argv[2])
same = len(a) == len(b) and all(
    str(ha) == str(hb)
    and ca.keys() == cb.keys()
    and all(np.array_equal(ca[k], cb[k], equal_nan=True) for k in ca)
    for (ha, ca), (hb, cb) in zip(a, b)
)
sys.exit(0 if same else 1)
PY
    else
        cmp -s "$1" "$2"
    fi
}
# As `check`, a shell script run with each binary as $Q in its own folder (for outputs on stdout
# and for several commands: tiles and their merge).
check_sh() {
    local label=$1 script=$2
    for which in old new; do
        local bin=$old
        [[ $which == new ]] && bin=$new
        rm -rf "$tmp/$which" && mkdir -p "$tmp/$which"
        (cd "$tmp/$which" && Q=$bin bash -c "$script" >/dev/null 2>"$tmp/$which.err") || {
            echo "| \`$label\` | $which failed: $(tail -1 "$tmp/$which.err") | no |"
            differ=1
            return
        }
    done
    compare "$label"
}
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
    compare "$label"
}
# Compares the files the two runs of `label` wrote, one row of the table.
compare() {
    local label=$1
    local files verdict=yes
    files=$(cd "$tmp/old" && find . -type f | sort)
    if [[ "$files" != "$(cd "$tmp/new" && find . -type f | sort)" ]]; then
        verdict="no (different files)"
    else
        for f in $files; do
            same "$tmp/old/$f" "$tmp/new/$f" || verdict="no ($f)"
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
# Path mode, the denoiser, adaptive sampling, the HDR output, tiles and merge, and the data the
# browser's host reads (issues 35 and 36). Stats are not compared: they hold times.
path=(--set 'shading.model="path"' --set image.samples=4 --set sun.intensity=3)
for backend in "gpu f32" "cpu f32" "cpu f64"; do
    set -- $backend
    check "render path --backend $1 --precision $2 (png, depth, steps, hdr)" \
        render "${size[@]}" "${path[@]}" --backend "$1" --precision "$2" \
        -o p.png --depth d.npy --steps s.npy --hdr h.exr
done
check "render --preset path-traced (lens, aces) --backend gpu" \
    render --preset path-traced "${size[@]}" --set image.samples=4 --backend gpu -o p.png --hdr h.exr
for model in phong path; do
    m=(--set "shading.model=\"$model\"" --set image.samples=8 --set sun.intensity=3)
    for backend in gpu cpu; do
        check "render $model --denoise atrous --backend $backend" \
            render "${size[@]}" "${m[@]}" --set 'image.denoise="atrous"' --backend "$backend" -o p.png --hdr h.exr
        check "render $model adaptive --backend $backend (png, hdr)" \
            render "${size[@]}" "${m[@]}" --set image.samples=32 --set path.noise_target=0.05 \
            --backend "$backend" -o p.png --hdr h.exr
        check "render $model adaptive --view samples --backend $backend" \
            render "${size[@]}" "${m[@]}" --set image.samples=32 --set path.noise_target=0.05 \
            --backend "$backend" --view samples -o v.png
    done
    check "render $model --hdr (phong: unclamped mean)" \
        render "${size[@]}" "${m[@]}" --backend gpu -o p.png --hdr h.exr
    check_sh "render $model --tile K/3, merge --backend gpu" \
        "mkdir parts && for k in 0 1 2; do \$Q render ${size[*]} --set 'shading.model=\"$model\"' \
         --set image.samples=8 --backend gpu --tile \$k/3 --hdr parts/\$k.exr || exit 1; done && \
         \$Q merge parts/0.exr parts/1.exr parts/2.exr -o m.png --hdr m.exr && rm -r parts"
done
check_sh "schema --json" '$Q schema --json > schema.json'
for preset in seed gallery path-traced deep-zoom; do
    check_sh "gpu-params --preset $preset --json" "\$Q gpu-params --preset $preset --json > params.json"
done
exit $differ
