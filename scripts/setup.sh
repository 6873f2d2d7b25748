#!/usr/bin/env bash
# First set-up command: installs Debian 12 packages (as root, or through sudo), builds Stormlight,
# installs it under /usr/local (the command, libstormlight, and the Python package `stormlight`
# into /usr/local/lib/python3.X/dist-packages, where Debian's python3 finds it), and renders two
# of Stormlight's own synthetic storms (datasets/) into out/ (EXR and PNG).
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(build-essential cmake pkg-config libvtk9-dev mpi-default-dev libnetcdf-dev netcdf-bin
  libopenexr-dev libgeographiclib-dev libfftw3-dev libpng-dev libcjson-dev xvfb xauth libgl1-mesa-dri
  proj-bin ffmpeg mpi-default-bin libgmt-dev gmt gmt-gshhg-low gmt-dcw clang libclang-rt-14-dev libomp-dev jq
  python3-dev python3-numpy python3-pytest python3-xarray python3-netcdf4 python3-matplotlib)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ "$(id -u)" -eq 0 ]; then sudo=""; else sudo="sudo"; fi
if [ ${#missing[@]} -gt 0 ]; then
  echo "installing: ${missing[*]}"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

cmake -S . -B build/release -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build/release -j"$(nproc)"
$sudo cmake --install build/release >/dev/null
$sudo ldconfig
/usr/bin/python3 -c "import stormlight" || { echo "setup: the Python package does not import"; exit 1; }

mkdir -p out
sl=build/release/app/stormlight
xvfb-run -a "$sl" render datasets/cumulonimbus.nc --out out/cumulonimbus.exr,out/cumulonimbus.png
xvfb-run -a "$sl" render datasets/stratocumulus.nc --out out/stratocumulus.exr,out/stratocumulus.png
echo "done: out/cumulonimbus.png, out/stratocumulus.png (and .exr); the executable is $sl"
