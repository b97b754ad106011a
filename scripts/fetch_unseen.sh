#!/bin/sh
# Downloads the three sets of public meshes that docs/REMESH.md and docs/LOD.md use as
# inputs never seen while tuning, at the commits their tables were made from, into
# DIR/alecjacobson, DIR/libigl and DIR/odedstein (about 45 MB; not in the repository).
# Each object's licence is its repository's (odedstein/meshes: the README beside each
# object names its author and licence).
#
#   scripts/fetch_unseen.sh DIR
#   SCANS=DIR/odedstein sh scripts/remesh_sweep.sh build "150 300" "4 5"
#
# Needs curl and python3 (for the one zipped mesh). Files already there are kept.
set -eu
dir=${1:?usage: scripts/fetch_unseen.sh DIR}

# fetch REPO COMMIT PATH OUT: one file, written whole or not at all.
fetch() {
  [ -s "$4" ] && return 0
  curl -fsSL --retry 3 "https://raw.githubusercontent.com/$1/$2/$3" -o "$4.part"
  mv "$4.part" "$4"
}

alec=alecjacobson/common-3d-test-models
alec_commit=8a4f8642acaf43f9cd7b67858a1502e1055ef202
mkdir -p "$dir/alecjacobson"
for name in alligator beast beetle beetle-alt cheburashka homer nefertiti ogre suzanne \
  teapot woody; do
  fetch "$alec" "$alec_commit" "data/$name.obj" "$dir/alecjacobson/$name.obj"
done
# The horse is stored zipped only (as a PLY file).
if [ ! -s "$dir/alecjacobson/horse.ply" ]; then
  fetch "$alec" "$alec_commit" data/horse.zip "$dir/alecjacobson/horse.zip"
  python3 -c 'import sys, zipfile; zipfile.ZipFile(sys.argv[1]).extract("horse.ply", sys.argv[2])' \
    "$dir/alecjacobson/horse.zip" "$dir/alecjacobson"
  rm -f "$dir/alecjacobson/horse.zip"
fi

igl=libigl/libigl-tutorial-data
igl_commit=c1f9ede366d02e3531ecbaec5e3769312f31cccd
mkdir -p "$dir/libigl"
for file in beetle.off bumpy.off bunny.off camel_b.obj cylinder.obj face.obj halftunnel.off \
  horse_quad.obj inspired_mesh.obj lilium.obj snail.obj truck.obj; do
  fetch "$igl" "$igl_commit" "$file" "$dir/libigl/$file"
done

oded=odedstein/meshes
oded_commit=835213277571d625722d25880c9c3010c6f45a5a
mkdir -p "$dir/odedstein"
for object in boot/boot brucewick/brucewick cat/cat-low-resolution \
  demosthenes/demosthenes-low-res falconstatue/falconstatue_boundary \
  fish/fish_low_resolution goathead/goathead hammer/hammer hand/hand_closed \
  human/human_man koala/koala_low_resolution lionstatue/lionstatue mushroom/mushroom \
  penguin/penguin plane/plane_holes scorpion/scorpion_low_resolution \
  skull/skull_low_resolution springer/springer stuffedtoy/stuffedtoy sword/sword \
  torus/torus wingnut/wingnut; do
  fetch "$oded" "$oded_commit" "objects/$object.obj" "$dir/odedstein/${object#*/}.obj"
done
echo "fetched into $dir/alecjacobson, $dir/libigl and $dir/odedstein"
