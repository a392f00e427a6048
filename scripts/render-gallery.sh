#!/usr/bin/env bash
# Renders the gallery (docs/images/gallery/NAME.png, one for every examples/NAME.moire) and
# the tutorial's steps (docs/images/tutorial-STEP.png, one for every docs/tutorial/STEP.moire).
# Run from the repository root after building: bash scripts/render-gallery.sh
#
# Each image is a plain `moire render` at the scene's own aspect: the gallery's 480 pixels
# wide at t = 3.6 s, the tutorial's 720 wide at t = 9 s, so that the animated scenes are
# caught in motion. tests/gallery_test.cpp renders every scene again the same way and fails
# when an image is missing or no longer what its scene draws: run this script after
# changing an example or a step of the tutorial.
set -euo pipefail
moire=${MOIRE:-build/bin/moire}

# The image size for scene $1: $2 pixels wide, at the aspect of its `size` (1200x800 when it
# sets none).
size_of() {
    local w=1200 h=800 line
    line=$(grep -Eo 'size *= *\( *[0-9]+ *, *[0-9]+ *\)' "$1" | head -n 1 || true)
    if [[ -n $line ]]; then
        read -r w h <<<"$(tr -dc '0-9,' <<<"$line" | tr ',' ' ')"
    fi
    echo "${2}x$((($2 * h + w / 2) / w))"
}
# render SCENE WIDTH TIME OUTPUT
render() {
    "$moire" render -q --compression 9 --size "$(size_of "$1" "$2")" --time "$3" "$1" -o "$4"
}

mkdir -p docs/images/gallery
rm -f docs/images/gallery/*.png
for scene in examples/*.moire; do
    render "$scene" 480 3.6 "docs/images/gallery/$(basename "$scene" .moire).png"
done

rm -f docs/images/tutorial-*.png
for scene in docs/tutorial/*.moire; do
    render "$scene" 720 9 "docs/images/tutorial-$(basename "$scene" .moire).png"
done
