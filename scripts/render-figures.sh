#!/usr/bin/env bash
# Renders the figures in docs/images from the examples and docs/scenes: the teaser's panels
# as split views (pattern left, envelope right), the spec's Fig. 5 (each layer, the pattern,
# the envelope with the fringe overlay, the ratio view) and Fig. 7 (the pattern and its
# envelope). Run from the repository root after building: bash scripts/render-figures.sh
# tests/teaser_test.cpp renders the teaser's panels again and checks each against its caption.
set -euo pipefail
moire=${MOIRE:-build/bin/moire}
out=docs/images
mkdir -p "$out"
render() { "$moire" render -q --compression 9 --size 480x320 "$@"; }

# The teaser (Fig. 1).
render --view split examples/two_rings.moire -o "$out/teaser-1-two-rings.png"
render --view split examples/terrain_contours.moire -o "$out/teaser-2-terrain.png"
render --view split examples/counter_spirals.moire -o "$out/teaser-3-counter-spirals.png"
render --view split examples/hexagonal_twist.moire -o "$out/teaser-4-hexagonal-twist.png"
render --view split examples/vortex_streamlines.moire -o "$out/teaser-5-vortices.png"
render --view split examples/walking_squares.moire -o "$out/teaser-6-one-walking-family.png"
render --view split examples/radial_fans.moire -o "$out/teaser-7-radial-fans.png"
render --view split examples/drifting_walks.moire -o "$out/teaser-8-drifting-walks.png"

# Fig. 5: the two ring families alone, together, averaged with {D in Z}, and the ratio view.
fig5=docs/scenes/fig5_rings.moire
sed '/origin = (17, 0)/d' "$fig5" | render - -o "$out/fig5-a-first-layer.png"
sed '/origin = (-17, 0)/d' "$fig5" | render - -o "$out/fig5-b-second-layer.png"
render "$fig5" -o "$out/fig5-c-superposition.png"
render "$fig5" --view envelope --overlay -o "$out/fig5-d-envelope-overlay.png"
render "$fig5" --view ratio -o "$out/fig5-e-ratio.png"

# Fig. 7: the (3, -1) fringe, and the envelope that keeps it.
render docs/scenes/fig7_lines.moire -o "$out/fig7-a-pattern.png"
render docs/scenes/fig7_lines.moire --view envelope -o "$out/fig7-c-envelope.png"
render docs/scenes/fig7_lines.moire --view ratio -o "$out/fig7-ratio.png"
