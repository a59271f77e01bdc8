#!/usr/bin/env bash
# Re-records the BehaviorTree.CPP 3.8 fixtures of the version 3 differential test.
#
#   tests/btcpp/v3/record.sh /path/to/BehaviorTree.CPP-3.8 [--count N] [--seed S]
#
# Builds and installs BehaviorTree.CPP from the checkout given (its 3.8.x tag; Release,
# shared, without examples, tests, tools, the manual selector and coroutines) under
# $BTCPP3_WORK (default /tmp/btcpp3-work), builds the harness (harness.cpp) against it,
# writes the random cases and the hand-made ones (cases/*.cases) with
# `cargo run -p integration-tests --bin btcpp3 -- cases`, runs them, and replaces
# fixtures/*.txt. With BTCPP3_INSTALL set to an installed BehaviorTree.CPP 3.8, the build
# is skipped. Needs cmake (pip install cmake), a C++17 compiler and cargo.
set -euo pipefail

here="$(cd "$(dirname "$0")" && pwd)"
repo="$(cd "$here/../../.." && pwd)"
src="${1:?usage: record.sh /path/to/BehaviorTree.CPP-3.8 [--count N] [--seed S]}"
shift
count=500
seed=1
while [ $# -gt 0 ]; do
  case "$1" in
    --count) count="$2"; shift 2 ;;
    --seed) seed="$2"; shift 2 ;;
    *) echo "unknown option $1" >&2; exit 2 ;;
  esac
done
work="${BTCPP3_WORK:-/tmp/btcpp3-work}"
jobs="${JOBS:-2}"
mkdir -p "$work"

echo "== BehaviorTree.CPP $(grep -m1 -o '<version>[^<]*' "$src/package.xml" | cut -c10-)"
install="${BTCPP3_INSTALL:-}"
if [ -z "$install" ]; then
  install="$work/install"
  # 3.8's CMakeLists asks for CMake 3.5 behaviour, which CMake 4 needs told.
  cmake -S "$src" -B "$work/build" -DCMAKE_BUILD_TYPE=Release -DBUILD_SHARED_LIBS=ON \
    -DBUILD_EXAMPLES=OFF -DBUILD_UNIT_TESTS=OFF -DBUILD_TOOLS=OFF \
    -DBUILD_MANUAL_SELECTOR=OFF -DENABLE_COROUTINES=OFF \
    -DCMAKE_POLICY_VERSION_MINIMUM=3.5 -DCMAKE_INSTALL_PREFIX="$install" >/dev/null
  cmake --build "$work/build" -j "$jobs" >/dev/null
  cmake --install "$work/build" >/dev/null
fi
cmake -S "$here" -B "$work/harness" -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$install" >/dev/null
cmake --build "$work/harness" >/dev/null
harness="$work/harness/harness"
export LD_LIBRARY_PATH="$install/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"

(cd "$repo" && cargo build -q -p integration-tests --bin btcpp3)
tool="$repo/target/debug/btcpp3"
fixtures="$here/fixtures"
mkdir -p "$fixtures"
rm -f "$fixtures"/*.txt
tmp="$work/run"
rm -rf "$tmp" && mkdir -p "$tmp"

# The random cases: 30% more than kept, since cases BehaviorTree.CPP refuses or runs away
# on, and clocked cases whose two runs disagree (a loaded machine), are left out.
total=$((count + count * 3 / 10))
chunk=100
n=0
for from in $(seq 0 $chunk $((total - 1))); do
  "$tool" cases "$seed" "$from" "$chunk" > "$tmp/in-$from.txt"
  ( "$harness" "$tmp/in-$from.txt" > "$tmp/out-$from.txt" ) &
  n=$((n + 1))
  if [ $((n % jobs)) -eq 0 ]; then wait; fi
done
wait
for from in $(seq 0 $chunk $((total - 1))); do cat "$tmp/out-$from.txt"; done | awk -v count="$count" -v dir="$fixtures" '
  /^case / { buf = ""; bad = 0 }
  /^(error|runaway)/ { bad = 1 }
  { buf = buf $0 "\n" }
  /^end$/ {
    if (bad) { next }
    if (kept < count) {
      file = sprintf("%s/random-%02d.txt", dir, int(kept / 100))
      printf "%s", buf > file
      kept++
    }
  }
  END { printf "kept %d random cases\n", kept > "/dev/stderr" }'

# The hand-made cases, each file as it is (a case BehaviorTree.CPP refuses shows its error).
for f in "$here"/cases/*.cases; do
  base="$(basename "$f" .cases)"
  "$tool" cases "$f" > "$tmp/$base.in"
  "$harness" "$tmp/$base.in" > "$fixtures/$base.txt"
done
"$tool" check "$fixtures"/*.txt | tail -1
du -sh "$fixtures"
