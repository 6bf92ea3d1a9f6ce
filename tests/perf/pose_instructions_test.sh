#!/bin/sh
# The central promise in instructions, not wall time: on CMU 01_01 (CMU units) at E = 50, the
# LOD pose path executes fewer instructions per character-frame than full detail, and each
# stays within the budget (full <= 4,500, LOD <= 3,500; measured 3,164 and 3,029
# when the plans became one contiguous record per clip frame). Counted
# with callgrind inside PoseEvaluatorJob::run alone (--toggle-collect), so import, clustering
# and plan building are left out, and the count is the same whatever else the machine does.
# Usage: pose_instructions_test.sh MOTIONLOD CLIP.bvh   (exit 77 = skipped: no valgrind)
set -eu
motionlod=$1
clip=$2
valgrind=${VALGRIND:-$(command -v valgrind || true)}
[ -n "$valgrind" ] || { echo "valgrind not installed: skipped"; exit 77; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
characters=100
frames=20

count() { # side -> instructions per character-frame
  "$valgrind" --tool=callgrind --callgrind-out-file="$out/$1.out" --toggle-collect='mlod::PoseEvaluatorJob::run*' \
    "$motionlod" bench-crowd "$clip" --characters $characters --frames $frames --threshold 50 --unit-scale cmu \
    --threads 1 --only "$1" --repetitions 1 --json >"$out/$1.json" 2>"$out/$1.err" ||
    { cat "$out/$1.err" >&2; exit 1; }
  total=$(sed -n 's/^summary: //p' "$out/$1.out")
  [ -n "$total" ] || { echo "no callgrind summary for $1" >&2; exit 1; }
  echo $((total / (characters * frames)))
}

full=$(count full)
lod=$(count lod)
echo "instructions per character-frame in PoseEvaluatorJob::run: full $full, LOD (E = 50) $lod"
[ "$full" -gt 0 ] && [ "$lod" -gt 0 ] || { echo "FAIL: nothing counted" >&2; exit 1; }
if [ "$lod" -ge "$full" ]; then
  echo "FAIL: the LOD pose path does not do less work than full detail" >&2
  exit 1
fi
if [ "$full" -gt 4500 ] || [ "$lod" -gt 3500 ]; then
  echo "FAIL: over budget (full <= 4500, LOD <= 3500 instructions per character-frame)" >&2
  exit 1
fi
