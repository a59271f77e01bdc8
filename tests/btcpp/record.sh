#!/usr/bin/env bash
# Re-records the BehaviorTree.CPP fixtures of the differential test.
#
#   tests/btcpp/record.sh /path/to/BehaviorTree.CPP [--count N] [--seed S]
#
# Builds and installs BehaviorTree.CPP from the checkout given (Release, shared, without
# Groot2/ZeroMQ, SQLite, tools, examples and tests) under $BTCPP_WORK (default
# /tmp/btcpp-work), builds the harness (harness.cpp) against it, writes the random
# cases (cargo run -p integration-tests --bin btcpp-cases) and the trees of
# BehaviorTree.CPP's own tests (cases/*.spec), runs them, and replaces fixtures/*.txt
# and fixtures/btlog/ (the Groot2 logs of every tenth random case and of every case
# the differential test compares only up to a restart by halt before start). With
# BTCPP_INSTALL set to an installed BehaviorTree.CPP, the build is skipped. Needs cmake
# (pip install cmake), a C++17 compiler and cargo.
set -euo pipefail

here="$(cd "$(dirname "$0")" && pwd)"
repo="$(cd "$here/../.." && pwd)"
src="${1:?usage: record.sh /path/to/BehaviorTree.CPP [--count N] [--seed S]}"
shift
count=1000
seed=1
while [ $# -gt 0 ]; do
  case "$1" in
    --count) count="$2"; shift 2 ;;
    --seed) seed="$2"; shift 2 ;;
    *) echo "unknown option $1" >&2; exit 2 ;;
  esac
done
work="${BTCPP_WORK:-/tmp/btcpp-work}"
jobs="${JOBS:-2}"
mkdir -p "$work"

echo "== BehaviorTree.CPP $(grep -m1 -o '<version>[^<]*' "$src/package.xml" | cut -c10-)"
install="${BTCPP_INSTALL:-}"
if [ -z "$install" ]; then
  install="$work/install"
  JOBS="$jobs" "$here/install-btcpp.sh" "$src" "$work/build" "$install" OFF
fi
cmake -S "$here" -B "$work/harness" -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$install" >/dev/null
cmake --build "$work/harness" >/dev/null
harness="$work/harness/harness"
# Scripts: BehaviorTree.CPP's script engine on the cases of cases/scripts.txt.
"$work/harness/scripts" "$here/cases/scripts.txt" > "$here/fixtures/scripts/scripts.txt"

# The random cases: more than needed, since cases BehaviorTree.CPP refuses or runs away
# on (a Repeat or Retry of -1 whose child never stops), and clocked cases whose two runs
# disagree (a loaded machine), are left out.
(cd "$repo" && cargo build -q -p integration-tests --bin btcpp-cases)
gen="$repo/target/debug/btcpp-cases"
fixtures="$here/fixtures"
mkdir -p "$fixtures/btlog"
rm -f "$fixtures"/random-*.txt "$fixtures"/btlog/*.btlog
tmp="$work/run"
rm -rf "$tmp" && mkdir -p "$tmp/logs"
total=$((count + count * 3 / 10))
chunk=100
n=0
for from in $(seq 0 $chunk $((total - 1))); do
  # Every case also writes its Groot2 log; some are kept (below).
  "$gen" "$seed" "$from" "$chunk" | awk -v dir="$tmp/logs" '
    /^case / { name = $2 }
    /^end$/ { print "btlog " dir "/" name ".btlog" }
    { print }' > "$tmp/in-$from.txt"
  ( "$harness" "$tmp/in-$from.txt" > "$tmp/out-$from.txt" ) &
  n=$((n + 1))
  if [ $((n % jobs)) -eq 0 ]; then wait; fi
done
wait
# Keep `count` cases BehaviorTree.CPP ran to the end, 100 per file.
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

# The Groot2 logs kept: every tenth random case, and every case that the differential
# test compares only up to the tick where halt before start restarted a branch (the
# .btlog test checks what it allows there).
(cd "$repo" && cargo build -q -p integration-tests --bin btcpp-check)
{
  grep -h '^case r[0-9]*0$' "$fixtures"/random-*.txt | cut -d' ' -f2
  "$repo/target/debug/btcpp-check" --restarted "$fixtures"/random-*.txt || true
} | sort -u | while read -r name; do cp "$tmp/logs/$name.btlog" "$fixtures/btlog/"; done
echo "kept $(ls "$fixtures"/btlog/*.btlog | wc -l) Groot2 logs" >&2

# Random trees with Script, ScriptCondition, Precondition and loop nodes and scripted
# attributes (never clocked): 300 kept, 100 per file, those BehaviorTree.CPP ran to the
# end.
rm -f "$fixtures"/scripted-*.txt
"$gen" --scripted "$seed" 0 400 | awk -v dir="$tmp/logs" '
    /^case / { name = $2 }
    /^end$/ { print "btlog " dir "/" name ".btlog" }
    { print }' > "$tmp/scripted-in.txt"
"$harness" "$tmp/scripted-in.txt" | awk -v dir="$fixtures" '
  /^case / { buf = ""; bad = 0 }
  /^(error|runaway)/ { bad = 1 }
  { buf = buf $0 "\n" }
  /^end$/ {
    if (bad) { next }
    if (kept < 300) {
      file = sprintf("%s/scripted-%02d.txt", dir, int(kept / 100))
      printf "%s", buf > file
      kept++
    }
  }
  END { printf "kept %d scripted cases\n", kept > "/dev/stderr" }'
# Their Groot2 logs: every kept case.
awk '/^case / { print $2 }' "$fixtures"/scripted-*.txt |
  while read -r name; do cp "$tmp/logs/$name.btlog" "$fixtures/btlog/"; done

# The trees of BehaviorTree.CPP's own tests.
# With their Groot2 logs, but for BehaviorTree.CPP's own tests'.
for f in "$here"/cases/*.spec; do
  base="$(basename "$f" .spec)"
  if [ "$base" = btcpp-tests ]; then
    "$gen" "$f" > "$tmp/$base.in"
  else
    "$gen" "$f" | awk -v dir="$fixtures/btlog" '
      /^case / { name = $2 }
      /^end$/ { print "btlog " dir "/" name ".btlog" }
      { print }' > "$tmp/$base.in"
  fi
  "$harness" "$tmp/$base.in" > "$fixtures/$base.txt"
done
du -sh "$fixtures"
