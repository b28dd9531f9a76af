#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# The longer fuzz campaign of the readers (Documentation/reliability.md): builds the libFuzzer
# targets with clang, ASan and UBSan in $SIGHTLINE_FUZZ_BUILD_DIR (default build-fuzz), writes
# the seed corpora from real files, then runs each target for RUNS executions (default 10^6) or
# SECONDS (default 3600), whichever comes first, and prints executions and findings per reader.
# Crashes, leaks, timeouts (> 10 s per input) and out-of-memory (> 2 GiB) stop a target and
# leave the input in $build/fuzz-findings/<reader>/; the grown corpus stays in
# $build/fuzz-corpus/<reader>/ for the next campaign.
# Usage: scripts/fuzz.sh [RUNS] [SECONDS] [READER...]    (readers: MIF TCK TrackVis SWC TRX NetCDFSpherical)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${SIGHTLINE_FUZZ_BUILD_DIR:-$root/build-fuzz}"
# shellcheck source=platform.sh
. "$root/scripts/platform.sh"
runs="${1:-1000000}"
seconds="${2:-3600}"
shift $(( $# > 2 ? 2 : $# ))
readers=("$@")
[ ${#readers[@]} -gt 0 ] || readers=(MIF TCK TrackVis SWC TRX NetCDFSpherical)
if [ ! -f "$build/build.ninja" ]; then
  CC="$SIGHTLINE_CC" CXX="$SIGHTLINE_CXX" cmake -S "$root" -B "$build" -G Ninja \
    -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPython3_EXECUTABLE=/usr/bin/python3 \
    -DSIGHTLINE_WRAP_PYTHON=OFF -DSIGHTLINE_BUILD_EXAMPLES=OFF \
    -DSIGHTLINE_BUILD_BENCHMARKS=OFF -DSIGHTLINE_FUZZ=ON
fi
targets=()
for r in "${readers[@]}"; do targets+=("SightlineFuzz${r}Reader"); done
cmake --build "$build" --target "${targets[@]}"
# The MIF seeds are cut from the SH data that the SHData fixture generates.
sh_data="$build/Testing/Data/sh"
[ -f "$sh_data/small_64D_sh_tournier07.mif" ] || (cd "$build" && ctest -R '^SHData.Generate$' >/dev/null)
seeds="$build/fuzz-seeds"
"$root/scripts/fuzz-corpus.sh" "$seeds" "$sh_data"
summary=()
for r in "${readers[@]}"; do
  corpus="$build/fuzz-corpus/$r"
  findings="$build/fuzz-findings/$r"
  mkdir -p "$corpus" "$findings"
  log="$build/fuzz-$r.log"
  status=0
  ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    LSAN_OPTIONS="suppressions=$root/Testing/Fuzz/lsan-suppressions.txt" \
    "$build/bin/SightlineFuzz${r}Reader" -runs="$runs" -max_total_time="$seconds" \
    -rss_limit_mb=2048 -timeout=10 -max_len=65536 -print_final_stats=1 \
    -artifact_prefix="$findings/" "$corpus" "$seeds/$r" >"$log" 2>&1 || status=$?
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  found=$(find "$findings" -type f | wc -l)
  summary+=("$r: ${execs:-?} executions, $found findings, exit $status (log $log)")
done
printf '%s\n' "${summary[@]}"
