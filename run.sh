#!/usr/bin/env bash
# RayMappers: set up, build and run. Two commands (see README.md):
#   ./run.sh demo   render the demo gallery on the bundled data into ./gallery, print a table
#   ./run.sh test   run the whole test suite with ctest
#   ./run.sh sanitize  the whole test suite built with AddressSanitizer and UBSan (build-asan)
# Each installs the Debian 12 packages that are missing (as root, or through sudo),
# configure once, build incrementally, and run under Xvfb (no display needed).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
build="${RAYMAPPERS_BUILD_DIR:-$here/build}"
mode="${1:-}"
case "$mode" in
  demo | test | build) ;;
  sanitize)
    # A build of its own: instrumented code, RelWithDebInfo for readable reports.
    build="${RAYMAPPERS_SANITIZE_BUILD_DIR:-$here/build-asan}"
    ;;
  *)
    echo "usage: $0 demo|test|sanitize|build" >&2
    exit 2
    ;;
esac

# ParaView 5.11 SDK (its own VTK), Embree 3, TBB, the -dev packages ParaView's CMake config
# asks for, Xvfb for headless rendering, LAMMPS, LIGGGHTS, galpy (with scipy) and PySPH for
# the generated data, matplotlib for plots.
packages=(
  build-essential cmake ninja-build pkg-config
  paraview paraview-dev python3-paraview
  libembree-dev libtbb-dev libgtest-dev libbenchmark-dev
  qtbase5-dev qttools5-dev libqt5svg5-dev libqt5x11extras5-dev qtxmlpatterns5-dev-tools
  libopenmpi-dev libutfcpp-dev libhdf5-dev libglew-dev liblz4-dev libtiff-dev
  libdouble-conversion-dev libogg-dev libtheora-dev libgl2ps-dev libjpeg-dev libpng-dev
  libfreetype-dev libxml2-dev libexpat1-dev liblzma-dev zlib1g-dev libavformat-dev
  libavcodec-dev libavutil-dev libswscale-dev libnetcdf-dev libboost-dev libgdal-dev
  xvfb xauth lammps liggghts openmpi-bin python3-numpy python3-matplotlib python3-scipy
  python3-galpy python3-pysph
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ "${#missing[@]}" -gt 0 ]; then
  echo "== installing ${#missing[@]} Debian packages: ${missing[*]}"
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

if [ ! -f "$build/CMakeCache.txt" ]; then
  echo "== configuring in $build"
  if [ "$mode" = sanitize ]; then
    cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DRAYMAPPERS_SANITIZE=ON
  else
    cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release
  fi
fi
echo "== building"
cmake --build "$build" -- -j"$(nproc)"

# Every program that opens a render window runs inside one Xvfb server. -noreset: an X
# server resets when its last client disconnects, and a window opened during that reset
# fails ("bad X server connection"); tests open and close many windows.
headless() { xvfb-run -a -s "-screen 0 1920x1080x24 -noreset" "$@"; }

case "$mode" in
  demo)
    headless pvpython "$here/Examples/gallery.py" --build "$build" --out "$here/gallery"
    ;;
  test | sanitize)
    # Under the sanitizers the tests carry the runtimes' options (and, for the pvpython,
    # pvbatch, pvserver and paraview tests, the preloaded runtimes) themselves: see
    # Testing/CMakeLists.txt.
    cd "$build"
    headless ctest --output-on-failure -j1 --timeout 1500
    ;;
  build) ;;
esac
