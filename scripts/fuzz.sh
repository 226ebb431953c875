#!/usr/bin/env bash
# make fuzz: builds the libFuzzer targets of fuzz/ with clang (build-fuzz/, DHDR_FUZZ=ON) and
# runs each for FUZZ_SECONDS (docs/development.md, "Fuzzing").
#   scripts/fuzz.sh [target...]      all targets when none is named
# Environment: FUZZ_SECONDS (60) per target, FUZZ_BUILD (build-fuzz), JOBS (nproc) for the
# build, FUZZ_RSS_MB (2048) and FUZZ_TIMEOUT (25 s) for one input, FUZZ_PARALLEL (1) targets
# run at a time.
# Each target's working corpus is FUZZ_BUILD/corpus/<target>, seeded from fuzz/corpus/<target>;
# what crashes (or leaks, runs out of memory or time) is saved in FUZZ_BUILD/artifacts/<target>/.
# Prints one line a target and exits 1 when any target left a new artifact.
set -euo pipefail
cd "$(dirname "$0")/.."

SECONDS_PER_TARGET=${FUZZ_SECONDS:-60}
BUILD=${FUZZ_BUILD:-build-fuzz}
JOBS=${JOBS:-$(nproc)}
RSS_MB=${FUZZ_RSS_MB:-2048}
TIMEOUT=${FUZZ_TIMEOUT:-25}
all_targets=(fuzz_lights fuzz_gltf_json fuzz_scene fuzz_channel_map fuzz_gbuffer fuzz_probes
             fuzz_ibl)
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=("${all_targets[@]}")

# clang and libFuzzer's runtime, as scripts/install-deps.sh installs the rest: only what is
# missing, apt untouched otherwise.
bash scripts/install-deps.sh
missing=()
for p in clang libclang-rt-14-dev; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "fuzz: installing ${missing[*]}"
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

cmake -S . -B "$BUILD" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
      -DDHDR_FUZZ=ON -DBUILD_TESTING=OFF >/dev/null
cmake --build "$BUILD" -j "$JOBS" --target "${targets[@]}"

# Leaks are reported (libFuzzer's default under AddressSanitizer); any UBSan report aborts.
export ASAN_OPTIONS=${ASAN_OPTIONS:-abort_on_error=0:allocator_may_return_null=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
# Leaks whose allocation passes through Debian's Assimp are its own (fuzz/lsan.supp says which).
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$PWD/fuzz/lsan.supp}

# One target: its corpus seeded, fuzzed, its line of the summary in $BUILD/.summary-<target>.
run_target() {
  local t=$1
  local corpus="$BUILD/corpus/$t" artifacts="$BUILD/artifacts/$t" log="$BUILD/$t.log"
  local marker="$BUILD/.start-$t"
  mkdir -p "$corpus" "$artifacts"
  [ -d "fuzz/corpus/$t" ] && cp -n fuzz/corpus/"$t"/* "$corpus"/ 2>/dev/null || true
  touch "$marker"
  echo "fuzz: $t for ${SECONDS_PER_TARGET} s (log: $log)"
  # Fork mode with crashes ignored: the run goes on past a crash, and every one is saved.
  "$BUILD/fuzz/$t" -fork=1 -ignore_crashes=1 -ignore_ooms=1 -ignore_timeouts=1 \
    -max_total_time="$SECONDS_PER_TARGET" -rss_limit_mb="$RSS_MB" -timeout="$TIMEOUT" \
    -artifact_prefix="$artifacts/" "$corpus" >"$log" 2>&1 || true
  # Executions: the last "#N: cov: …" status line of fork mode.
  local execs files found kinds line
  execs=$(grep -oE '^#[0-9]+: cov' "$log" | tail -1 | tr -dc '0-9')
  files=$(find "$corpus" -type f | wc -l)
  found=$(find "$artifacts" -type f -newer "$marker" | wc -l)
  kinds=$(find "$artifacts" -type f -newer "$marker" -printf '%f\n' | sed 's/-.*//' | sort |
          uniq -c | awk '{printf "%s%s %s", (n++ ? ", " : ""), $1, $2}')
  rm -f "$marker"
  line=$(printf '%-18s %6s s  %10s executions  corpus %5s files  crashes %s' "$t" \
         "$SECONDS_PER_TARGET" "${execs:-0}" "$files" "$found")
  [ "$found" -gt 0 ] && line="$line  ($kinds in $artifacts/)"
  echo "$line" >"$BUILD/.summary-$t"
}

# FUZZ_PARALLEL targets at a time (default 1: the machine is shared).
PARALLEL=${FUZZ_PARALLEL:-1}
for t in "${targets[@]}"; do
  rm -f "$BUILD/.summary-$t"
  while [ "$(jobs -rp | wc -l)" -ge "$PARALLEL" ]; do wait -n || true; done
  run_target "$t" &
done
wait

# An input that crashed its process left that process's temporary directory behind
# (fuzz/targets.h): the directories of processes no longer running are removed.
for d in /dev/shm/dhdr-fuzz-* "${TMPDIR:-/tmp}"/dhdr-fuzz-*; do
  [ -d "$d" ] && ! kill -0 "${d##*-}" 2>/dev/null && rm -rf "$d"
done

failed=0
echo
echo "fuzz summary:"
for t in "${targets[@]}"; do
  line=$(cat "$BUILD/.summary-$t" 2>/dev/null || echo "$t: no result")
  echo "  $line"
  case "$line" in *"crashes 0"*) ;; *) failed=1 ;; esac
  rm -f "$BUILD/.summary-$t"
done
exit $failed
