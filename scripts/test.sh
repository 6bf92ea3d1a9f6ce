#!/usr/bin/env bash
# Builds and runs every test: the main build (GCC, warnings as errors: unit, io, CLI and
# UI tests) and a clang ASan+UBSan build of the runtime, core and io tests with a short
# libFuzzer run of the importer.
set -uo pipefail
cd "$(dirname "$0")/.."

bash scripts/install-deps.sh || exit 1
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-$(mktemp -d)}"
chmod 700 "$XDG_RUNTIME_DIR"
jobs=$(nproc)
failed=0

run_suite() { # name build-dir ctest-exclude-regex cmake-options...
  local name=$1 dir=$2 exclude=$3
  shift 3
  echo "== $name: configure and build ($dir)"
  if ! cmake -S . -B "$dir" -G Ninja -DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DMLOD_WERROR=ON "$@" ||
     ! cmake --build "$dir"; then
    echo "== $name: BUILD FAILED"
    failed=1
    return
  fi
  echo "== $name: ctest"
  (cd "$dir" && ctest -j"$jobs" --output-on-failure ${exclude:+-E "$exclude"}) || failed=1
}

# MLOD_UNITY: the libraries compile in batches (CMakeLists.txt), a shorter clean build.
run_suite "main build" build "" -DCMAKE_BUILD_TYPE=Release -DMLOD_UNITY=ON
# The sanitizer build leaves out the sweeps over every character (MeshLodCharacters,
# BudgetSweep, SkinDeviationOnCharacters) and the longest budget-cache run (an edit of each
# kind): 542 of its 1,910 test seconds in a run on a loaded 2-core machine (the first two,
# about 150 in an earlier one). The main build
# runs them; the code they drive runs under the sanitizers in the single-character tests of
# the same claims and the other two LodBudgetCache tests.
run_suite "sanitizer build" build-asan \
  '^MeshLodCharacters\.|/BudgetSweep\.|/SkinDeviationOnCharacters\.|^LodBudgetCache\.AnEditIsNeverAnsweredFromTheCache$' \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ -DMLOD_UNITY=ON \
  -DMLOD_BUILD_QT=OFF -DMLOD_BUILD_BENCH=OFF -DMLOD_SANITIZE=ON -DMLOD_FUZZ=ON

if [ "$failed" -ne 0 ]; then
  echo "== FAILED: see the ctest output above"
  exit 1
fi
echo "== all test suites passed"
