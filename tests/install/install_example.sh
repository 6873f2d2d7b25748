#!/usr/bin/env bash
# install_example.sh BUILD SOURCE STORMLIGHT WORK STORM: installs the build into WORK/prefix, builds
# docs/examples/render_frame.c against that copy of libstormlight twice, with pkg-config and with
# CMake's find_package(Stormlight), and renders STORM with each; both frames must be the frame
# `stormlight render --cpu-composite` draws of it, bit for bit (float EXR).
set -euo pipefail
build=$1 src=$2 sl=$3 work=$4 storm=$5
rm -rf "$work" && mkdir -p "$work"
prefix=$work/prefix
cmake --install "$build" --prefix "$prefix" >/dev/null
export PKG_CONFIG_PATH=$prefix/lib/pkgconfig
cc -std=c11 -Wall -Wextra -Werror "$src/docs/examples/render_frame.c" $(pkg-config --cflags --libs stormlight) \
  -o "$work/render_frame_pc"
cmake -S "$src/docs/examples" -B "$work/example" -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$work/example" >/dev/null
export LD_LIBRARY_PATH=$prefix/lib
opts=(--width 160 --height 120 --sun-azimuth 130 --sun-elevation 30)
"$work/render_frame_pc" "$storm" "$work/pc.exr" "${opts[@]}"
"$work/example/render_frame" "$storm" "$work/cmake.exr" "${opts[@]}"
"$sl" render "$storm" --cpu-composite --float --quiet --out "$work/render.exr" "${opts[@]}"
"$sl" compare "$work/render.exr" "$work/pc.exr" --threshold 0
"$sl" compare "$work/render.exr" "$work/cmake.exr" --threshold 0
echo "render_frame.c built with pkg-config and with find_package draws render's frame"
