#!/usr/bin/env bash
# Renders docs/gallery/*.png (docs/gallery.md): the seed's look before and after, and each of
# issue 11's features on its own, at 384x384. Usage: scripts/gallery.sh [QJULIA_BINARY]
set -euo pipefail
cd "$(dirname "$0")/.."
q=${1:-target/release/qjulia}
out=docs/gallery
mkdir -p "$out"
size=(--width 384 --height 384)
r() { local name=$1; shift; "$q" render "${size[@]}" "$@" -o "$out/$name.png" --stats "/tmp/gallery-$name.json"; }
r seed
r gallery --preset gallery
r samples --set image.samples=16
r soft-shadows --set light.radius=0.3
r occlusion --set shading.ambient=0.3 --set shading.occlusion=1
r orbit-trap --set 'shading.colouring="orbit_trap"'
r cut --set cut.enabled=true --set 'cut.normal=[0, 0, 1]' --set cut.offset=0.0
# Path mode's two presets, at their own 512x512.
"$q" render --preset path-traced -o "$out/path-traced.png" --stats /tmp/gallery-path-traced.json
"$q" render --preset path-gallery -o "$out/path-gallery.png" --stats /tmp/gallery-path-gallery.json
# The atmosphere (docs/book/atmosphere.md): an HDR environment, light shafts in fog, and phong
# mode's glow.
"$q" render --preset environment -o "$out/environment.png" --stats /tmp/gallery-environment.json
"$q" render --preset fog-shafts -o "$out/fog-shafts.png" --stats /tmp/gallery-fog-shafts.json
"$q" render --preset glow -o "$out/glow.png" --stats /tmp/gallery-glow.json
# The denoiser (docs/book/denoise.md): the path-traced preset at 256x256, 16 samples noisy and
# denoised, and 1,024 samples as the reference, side by side (ImageMagick's montage).
t=(--preset path-traced --width 256 --height 256)
"$q" render "${t[@]}" --set image.samples=16 -o /tmp/gallery-noisy.png --stats /tmp/gallery-noisy.json
"$q" render "${t[@]}" --set image.samples=16 --set 'image.denoise="atrous"' -o /tmp/gallery-denoised.png --stats /tmp/gallery-denoised.json
"$q" render "${t[@]}" --set image.samples=1024 -o /tmp/gallery-reference.png --stats /tmp/gallery-reference.json
montage /tmp/gallery-noisy.png /tmp/gallery-denoised.png /tmp/gallery-reference.png -tile 3x1 -geometry 256x256+2+2 "$out/denoise-triple.png"
