#!/usr/bin/env bash
# Second set-up command: builds and runs the test suite (everything but the 'slow' label).
# The unit tests run twice: under AddressSanitizer + UndefinedBehaviorSanitizer, and in the
# release build with the rest of the suite (regression, CLI, VTK under a virtual X server).
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc)

cmake -S . -B build/asan -DSL_SANITIZE=ON -DSL_BUILD_APP=OFF -DCMAKE_BUILD_TYPE=Debug >/dev/null
cmake --build build/asan -j"$jobs"
ASAN_OPTIONS=detect_leaks=1 LSAN_OPTIONS=suppressions=$PWD/tests/lsan.supp \
  ctest --test-dir build/asan -L unit --output-on-failure -j"$jobs"

cmake -S . -B build/release -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build/release -j"$jobs"
# -noreset: no server reset between tests, which refuses a connection arriving meanwhile (app/x_display.h)
xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" ctest --test-dir build/release -LE slow --output-on-failure

# libFuzzer (only where clang is installed): the storm reader and the scene parser, 30 s each.
bash tests/fuzz/run.sh 30
