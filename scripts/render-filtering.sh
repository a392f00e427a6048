#!/usr/bin/env bash
# Renders the pictures of docs/filtering.md's "Before and after": every scene
# docs/filtering/NAME.moire drawn 480 pixels wide with --filter point and with --filter mean
# (docs/images/filtering-NAME-point.png, -mean.png), and the hairline scene also drawn 6 times
# larger and box-downsampled to the same 480 pixels (docs/images/filtering-hairline-print.png:
# the tone a print of the frame has). Run from the repository root after building:
#   bash scripts/render-filtering.sh
# tests/filtering_pictures_test.cpp renders every scene again the same way and fails when a
# picture is missing or no longer what its scene draws: run this script after changing the
# filter or a scene here. The box filter is ffmpeg's `area` scaler, which averages each 6x6
# block of a whole-number reduction. A scene whose comment holds a line `// render: FLAGS` (a
# morph half-way through its change: `--time 0.5`) is drawn with those flags too.
set -euo pipefail
moire=${MOIRE:-build/bin/moire}
ffmpeg=${FFMPEG:-ffmpeg}
size=480x320

rm -f docs/images/filtering-*.png
for scene in docs/filtering/*.moire; do
    name=$(basename "$scene" .moire)
    read -r -a flags <<<"$(sed -n 's|^// render: ||p' "$scene")"
    for filter in point mean; do
        "$moire" render -q --compression 9 --size "$size" --filter "$filter" "${flags[@]}" \
            "$scene" -o "docs/images/filtering-$name-$filter.png"
    done
done

# The print: 2880x1920 under the default filter, each 6x6 block averaged.
big=$(mktemp --suffix=.png)
trap 'rm -f "$big"' EXIT
"$moire" render -q --compression 1 --size 2880x1920 docs/filtering/hairline.moire -o "$big"
"$ffmpeg" -loglevel error -y -i "$big" -vf "scale=480:320:flags=area" \
    -pix_fmt rgb24 docs/images/filtering-hairline-print.png
