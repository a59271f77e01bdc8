#!/usr/bin/env bash
# Re-records tests/btcpp/fixtures/groot2/session.txt: what BehaviorTree.CPP's
# Groot2Publisher answers to the requests Groot2 sends, while a tree with scripted
# leaves ticks (publisher.cpp, the fixture's tree.xml), asked through libzmq by
# record.py.
#
#   tests/btcpp/groot2/record.sh /path/to/BehaviorTree.CPP
#
# Builds and installs BehaviorTree.CPP from the checkout given (Release, shared, WITH
# its Groot2 interface; its vendored cppzmq finds libzmq through pkg-config: on Debian
# `apt-get install libzmq3-dev`) under $BTCPP_WORK (default /tmp/btcpp-groot2-work),
# builds publisher.cpp against it, installs pyzmq (which bundles libzmq) into a venv
# there, and runs record.py. With BTCPP_INSTALL set to an installed BehaviorTree.CPP
# built with BTCPP_GROOT_INTERFACE=ON, the build is skipped. Needs cmake (pip install
# cmake), a C++17 compiler and python3 with venv. The fixture was recorded with
# release 4.10.0.
set -euo pipefail

here="$(cd "$(dirname "$0")" && pwd)"
src="${1:?usage: record.sh /path/to/BehaviorTree.CPP}"
work="${BTCPP_WORK:-/tmp/btcpp-groot2-work}"
port="${PORT:-24667}"
mkdir -p "$work"
install="${BTCPP_INSTALL:-}"
if [ -z "$install" ]; then
  install="$work/install"
  "$here/../install-btcpp.sh" "$src" "$work/build" "$install" ON
fi
cmake -S "$here" -B "$work/publisher" -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$install" >/dev/null
cmake --build "$work/publisher" >/dev/null
python3 -m venv "$work/venv"
"$work/venv/bin/pip" install -q pyzmq
out="$here/../fixtures/groot2"
mkdir -p "$out"
"$work/venv/bin/python" "$here/record.py" "$work/publisher/publisher" "$out/tree.xml" "$port" > "$out/session.txt.new"
mv "$out/session.txt.new" "$out/session.txt"
echo "wrote $(grep -c '^request' "$out/session.txt") requests and replies to tests/btcpp/fixtures/groot2/session.txt"
