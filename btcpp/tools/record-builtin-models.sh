#!/usr/bin/env bash
# Re-records btcpp/src/btlog/builtin-models.xml: the models of BehaviorTree.CPP's
# built-in nodes as its FileLogger2 writes them into every .btlog (their order and
# the order of their ports are those of the C++ standard library it was built with).
#
#   btcpp/tools/record-builtin-models.sh /path/to/installed/BehaviorTree.CPP
#
# The prefix is where BehaviorTree.CPP was installed (it has include/ and lib/); the
# fixtures were recorded with release 4.10.0 built by g++ 12 (libstdc++).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
prefix="${1:?usage: record-builtin-models.sh /path/to/installed/BehaviorTree.CPP}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
g++ -std=c++17 -O1 -I"$prefix/include" "$here/builtin_models.cpp" -L"$prefix/lib" \
  -lbehaviortree_cpp -lpthread -Wl,-rpath,"$prefix/lib" -o "$work/builtin_models"
"$work/builtin_models" > "$here/../src/btlog/builtin-models.xml"
echo "wrote btcpp/src/btlog/builtin-models.xml"
