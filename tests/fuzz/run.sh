#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (AddressSanitizer + UndefinedBehaviorSanitizer) and runs
# each for a bounded time: the reader on storm-like NetCDF files built from the fuzzer's bytes
# (fuzz_reader.c says why not raw header bytes), the scene parser on mutated scene files. Usage: tests/fuzz/run.sh [SECONDS per target, default 30].
# Skips (exit 0) without clang. A crash or sanitizer report fails with the reproducer's path.
set -euo pipefail
cd "$(dirname "$0")/../.."
seconds=${1:-30}
cc=$(command -v clang-14 || command -v clang || true)
cxx=$(command -v clang++-14 || command -v clang++ || true)
if [ -z "$cc" ] || [ -z "$cxx" ]; then
  echo "fuzz: clang not found, skipped"
  exit 0
fi
build=build/fuzz
flags="-fsanitize=address,undefined,fuzzer-no-link -fno-sanitize-recover=undefined -fno-omit-frame-pointer -g -O1"
cmake -S . -B $build -DCMAKE_C_COMPILER="$cc" -DCMAKE_CXX_COMPILER="$cxx" -DSL_BUILD_APP=OFF -DSL_FUZZ=ON \
  -DCMAKE_BUILD_TYPE=Debug -DCMAKE_C_FLAGS="$flags" -DCMAKE_CXX_FLAGS="$flags" \
  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" >/dev/null
cmake --build $build -j"$(nproc)" --target fuzz_reader fuzz_scene >/dev/null

# Seeds: a few pseudo-random byte strings for the reader (each builds a storm-like file), the bundled
# scene files for the parser.
corpus=$build/corpus
rm -rf "$corpus" && mkdir -p "$corpus/reader" "$corpus/scene"
# Seeds and the fuzzer's own seed are fixed, and each target stops after a fixed number of runs
# (or the time bound, whichever comes first): CI replays the same exploration every time, so a
# pass here is a pass there. For a longer, varied search: SL_FUZZ_SEED=0 tests/fuzz/run.sh 600.
fuzz_seed=${SL_FUZZ_SEED:-1}
for i in 1 2 3 4; do
  LC_ALL=C awk -v s="$i" 'BEGIN { srand(s); for (k = 0; k < 2048; k++) printf "%c", int(rand() * 256) }' \
    >"$corpus/reader/random$i"
done
# Inputs that once failed (tests/fuzz/regressions) run first, every time.
cp tests/fuzz/regressions/reader-* "$corpus/reader/"
cp datasets/scenes/*.json "$corpus/scene/"

export ASAN_OPTIONS=detect_leaks=1:allocator_may_return_null=1:max_allocation_size_mb=1536
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
declare -A runs=([reader]=20000 [scene]=300000)
for target in reader scene; do
  mkdir -p $build/artifacts/$target
  limit="-runs=${runs[$target]}"
  [ "$fuzz_seed" = 0 ] && limit=""
  echo "fuzz: $target for ${seconds} s"
  $build/tests/fuzz/fuzz_$target "$corpus/$target" -seed="$fuzz_seed" $limit -max_total_time="$seconds" -rss_limit_mb=3072 -malloc_limit_mb=2048 -max_len=65536 \
    -timeout=20 -print_final_stats=1 -artifact_prefix=$build/artifacts/$target/ 2>$build/fuzz_$target.log ||
    { tail -40 $build/fuzz_$target.log; echo "fuzz: $target FAILED (reproducer in $build/artifacts/$target/)"; exit 1; }
  grep -E "stat::number_of_executed_units|stat::peak_rss_mb" $build/fuzz_$target.log | tr '\n' ' '
  echo
done
