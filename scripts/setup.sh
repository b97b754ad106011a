#!/usr/bin/env bash
# Installs the Debian 12 packages that building and testing osdmra needs.
#
# Idempotent and quiet: dpkg decides what is missing, apt is only touched when
# something is, and a machine that has everything gets no output at all.
set -euo pipefail

packages=(
  build-essential  # g++, make
  cmake
  libosd-dev       # OpenSubdiv (Far, Sdc, Vtr, Osd CPU)
  libeigen3-dev
  libgtest-dev
  libbenchmark-dev # bench/ (OSDMRA_BUILD_BENCH=ON)
  libglfw3-dev
  libmeshoptimizer-dev # bench/: the simplification peer of level-of-detail extraction
  libdraco-dev     # bench/: the peer of the geometry codec (Google Draco)
  gnuplot-nox      # osdmra sweep --plot
  libgl-dev        # viewer/: OpenGL
  libimgui-dev     # viewer/: Dear ImGui and its GLFW/OpenGL3 backends (sources)
  libstb-dev       # viewer/: PNG screenshots (stb_image_write)
  xvfb             # viewer test: an X server without a screen
  xauth            # xvfb-run needs it
  libgl1-mesa-dri  # llvmpipe: OpenGL on the CPU
)

missing=()
for p in "${packages[@]}"; do
  # `dpkg -s` also succeeds for removed packages whose config files remain, so
  # look at the status line rather than the exit code.
  dpkg -s "$p" 2>/dev/null | grep -q '^Status: install ok installed' || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0

if [ "$(id -u)" -eq 0 ]; then
  as_root=()
elif command -v sudo >/dev/null 2>&1; then
  as_root=(sudo)
else
  echo "setup.sh: missing packages: ${missing[*]}" >&2
  echo "setup.sh: not root and no sudo; install them as root and rerun" >&2
  exit 1
fi

echo "setup.sh: installing ${missing[*]}"
log=$(mktemp)
trap 'rm -f "$log"' EXIT
# `env` because sudo drops the caller's environment.
run_apt() { "${as_root[@]}" env DEBIAN_FRONTEND=noninteractive apt-get -q -y "$@" >>"$log" 2>&1; }
if ! run_apt update || ! run_apt install --no-install-recommends "${missing[@]}"; then
  cat "$log" >&2
  echo "setup.sh: apt-get failed" >&2
  exit 1
fi
