#!/bin/sh
# Regenerates docs/COMPRESSION.md and its plots: rate-distortion of osdmra's codec and
# of Draco on the bundled head (both schemes) and on J = 5 remeshes (about 300 base
# faces) of five public scans of ../shared/data/scans (or $SCANS), and with UNSEEN=DIR
# (scripts/fetch_unseen.sh DIR) of six meshes never used for tuning.
#
#   scripts/codec_docs.sh [BUILD_DIR]   (default: build, configured with
#                                        -DOSDMRA_BUILD_BENCH=ON; needs libdraco-dev
#                                        and gnuplot)
# About 5 minutes on 2 cores (2026-12-03). The CSV files stay in docs/compression-data/.
set -eu
build=${1:-build}
scans=${SCANS:-../shared/data/scans}
cmake --build "$build" -j2 --target osdmra_codec_rd
work=docs/compression-data  # the measurements the tables and plots are made from
mkdir -p "$work"
rm -f "$work"/*.csv
rd="$build/bench/osdmra_codec_rd"
# Fixed wavelets (compress's default) unless the name says otherwise: quasi-wavelets
# need their corrections solved in the decoder, lazy ones none but cost PSNR.
"$rd" data/igea-oct6.obj --name igea-loop --scheme loop --csv "$work/01-igea-loop.csv"
"$rd" data/igea-oct6.obj --name igea-linear --scheme linear --csv "$work/02-igea-linear.csv"
"$rd" data/igea-oct6.obj --name igea-loop-quasi --wavelets quasi \
  --csv "$work/03-igea-loop-quasi.csv"
"$rd" data/igea-oct6.obj --name igea-loop-lazy --wavelets lazy --csv "$work/04-igea-loop-lazy.csv"
"$rd" "$scans/spot.obj" --remesh --base-faces 300 --levels 5 --name spot-quasi --wavelets quasi \
  --csv "$work/05-spot-quasi.csv"
# The scans' remeshes with the scheme compress chooses (the polyhedral one, see the
# intro), and spot's with Loop beside it.
"$rd" "$scans/spot.obj" --remesh --base-faces 300 --levels 5 --name spot-loop --scheme loop \
  --csv "$work/11-spot-loop.csv"
i=6
for name in stanford-bunny spot rocker-arm fandisk armadillo; do
  "$rd" "$scans/$name.obj" --remesh --base-faces 300 --levels 5 --name "$name" \
    --csv "$work/$(printf %02d $i)-$name.csv"
  i=$((i + 1))
done
# Meshes never used for tuning (scripts/fetch_unseen.sh DIR; UNSEEN=DIR): the same
# comparison, a summary row each. Without UNSEEN the rows of the last run stay.
if [ -n "${UNSEEN:-}" ]; then
  rm -f "$work"/unseen/*.csv
  mkdir -p "$work/unseen"
  for path in odedstein/hand_closed.obj odedstein/lionstatue.obj libigl/bunny.off \
    libigl/camel_b.obj alecjacobson/homer.obj alecjacobson/nefertiti.obj; do
    name="$(dirname "$path")-$(basename "$path" | sed 's/\.[a-z]*$//')"
    "$rd" "$UNSEEN/$path" --remesh --base-faces 300 --levels 5 --name "$name" \
      --csv "$work/unseen/$name.csv"
  done
fi
python3 scripts/codec_docs.py docs/COMPRESSION.md docs/images "$work"/*.csv \
  --unseen "$work"/unseen/*.csv
echo "wrote docs/COMPRESSION.md"
