#!/bin/sh
# A benchmark, not a pass/fail: instructions per character-frame of the pose path, full
# detail and the LOD (E = 50 cm·deg), on each clip given (CMU units). Counted with callgrind
# inside PoseEvaluatorJob::run alone (--toggle-collect), so import, clustering and plan
# building are left out and the count is the same whatever else the machine does. It fails
# only when nothing could be counted; the speed claims and their figures are in
# docs/architecture.md and `motionlod bench-crowd` (the issue's budget: full <= 4,500, LOD
# <= 0.75 x full).
# Usage: pose_instructions_test.sh MOTIONLOD CLIP.bvh...   (exit 77 = skipped: no valgrind)
set -eu
motionlod=$1
shift
valgrind=${VALGRIND:-$(command -v valgrind || true)}
[ -n "$valgrind" ] || { echo "valgrind not installed: skipped"; exit 77; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
characters=100
frames=20

count() { # clip side -> instructions per character-frame
  "$valgrind" --tool=callgrind --callgrind-out-file="$out/run.out" --toggle-collect='mlod::PoseEvaluatorJob::run*' \
    "$motionlod" bench-crowd "$1" --characters $characters --frames $frames --threshold 50 --unit-scale cmu \
    --threads 1 --only "$2" --repetitions 1 --json >"$out/run.json" 2>"$out/run.err" ||
    { cat "$out/run.err" >&2; exit 1; }
  total=$(sed -n 's/^summary: //p' "$out/run.out")
  [ -n "$total" ] && [ "$total" -gt 0 ] || { echo "no callgrind summary for $1 ($2)" >&2; exit 1; }
  echo $((total / (characters * frames)))
}

echo "instructions per character-frame in PoseEvaluatorJob::run ($characters characters x $frames frames, one thread)"
printf '%-24s %8s %8s %7s\n' clip full "LOD E50" "LOD/full"
for clip in "$@"; do
  full=$(count "$clip" full)
  lod=$(count "$clip" lod)
  printf '%-24s %8d %8d %7s\n' "$(basename "$clip")" "$full" "$lod" "$(awk "BEGIN { printf \"%.2f\", $lod / $full }")"
done
