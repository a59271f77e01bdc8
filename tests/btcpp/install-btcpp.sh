#!/usr/bin/env bash
# Builds BehaviorTree.CPP from a checkout and installs it, for the recording scripts
# (record.sh, groot2/record.sh): Release, shared, without SQLite logging, tools,
# examples and tests; with or without its Groot2 interface (which needs libzmq).
#
#   tests/btcpp/install-btcpp.sh SOURCE BUILD_DIR PREFIX ON|OFF
set -euo pipefail
src="${1:?usage: install-btcpp.sh SOURCE BUILD_DIR PREFIX ON|OFF}"
build="${2:?build directory}"
prefix="${3:?install prefix}"
groot="${4:?ON or OFF: build the Groot2 interface}"
cmake -S "$src" -B "$build" -DCMAKE_BUILD_TYPE=Release -DBTCPP_SHARED_LIBS=ON \
  -DBTCPP_BUILD_TOOLS=OFF -DBTCPP_EXAMPLES=OFF -DBUILD_TESTING=OFF \
  -DBTCPP_GROOT_INTERFACE="$groot" -DBTCPP_SQLITE_LOGGING=OFF \
  -DCMAKE_INSTALL_PREFIX="$prefix" >/dev/null
cmake --build "$build" -j "${JOBS:-2}" >/dev/null
cmake --install "$build" >/dev/null
