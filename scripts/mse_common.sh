# What scripts/adaptive_efficiency.sh and scripts/streams_cost.sh share, sourced by both after
# they set NEW, SIZE and REF: the example that measures MSEs, a scratch folder, the three scenes
# (the path-traced preset, the path-gallery preset and a smooth Lambert one: the unit ball, path
# traced, no specular lobe), a render of one of them, and a scene's two references.
STUDY=target/release/examples/adaptive_study
[ -x "$STUDY" ] || { echo "$STUDY is missing: cargo build --release --example adaptive_study"; exit 2; }
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT

scenes=(
    "path-traced|--preset path-traced"
    "path-gallery|--preset path-gallery"
    "lambert|--preset unit-ball --set shading.model=\"path\" --set material.specular=0"
)
render() { # binary, output stem, scene arguments..., then keys: STEM.exr, .json and .png
    local bin=$1 out=$2
    shift 2
    # shellcheck disable=SC2068
    "$bin" render $@ --width "$SIZE" --height "$SIZE" --hdr "$out.exr" --stats "$out.json" \
        -o "$out.png" >/dev/null 2>&1
}
references() { # scene name, scene arguments: $WORK/NAME-ref-a.exr and -ref-b.exr, REF `random`
    # samples each, with seeds of their own, by NEW
    render "$NEW" "$WORK/$1-ref-a" "$2" --set 'path.sampler="random"' \
        --set image.samples="$REF" --set path.seed=90001
    render "$NEW" "$WORK/$1-ref-b" "$2" --set 'path.sampler="random"' \
        --set image.samples="$REF" --set path.seed=90002
}
