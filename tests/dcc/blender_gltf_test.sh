#!/bin/sh
# blender_gltf_test.sh MOTIONLOD CHECK_BLENDER MODELS OUT_DIR
# Exports CMU 01_01 (motion only) and BCN_Epileptic (skinned) to glTF, as one file and as
# one file per level, imports each into Blender (check-blender.sh) and checks: one armature
# with every joint as a bone, one action per level and clip, the level meshes, of which one
# is visible (the coarser levels of a combined file present but hidden). Exit 77
# (ctest: skipped) when there is no Blender.
set -eu
motionlod=$1 check=$2 models=$3 out=$4
blender=${BLENDER:-}
if [ -z "$blender" ] || [ "${blender%NOTFOUND}" != "$blender" ] || ! command -v "$blender" >/dev/null 2>&1; then
  echo "skipped: Blender is not installed (apt install blender python3-numpy)"
  exit 77
fi
export BLENDER="$blender"
rm -rf "$out"
mkdir -p "$out"
failures=0
fail() {
  echo "FAIL: $*"
  failures=$((failures + 1))
}
# expect FILE ARMATURES BONES MESHES ACTIONS VISIBLE_MESHES
expect() {
  summary=$("$check" "$1" | tee "$1.blender.txt" | grep '^summary: ') || { fail "$1: Blender did not import it"; cat "$1.blender.txt"; return; }
  want="summary: armatures=$2 bones=$3 meshes=$4 actions=$5 empties=0 visible_meshes=$6"
  case "$summary" in
    "$want") echo "ok: $1: $summary" ;;
    *) fail "$1: $summary, expected $want"; cat "$1.blender.txt" ;;
  esac
}
joints() { "$motionlod" info "$1" --json | python3 -c 'import json,sys; print(len(json.load(sys.stdin)["joints"]))'; }

cmu="$models/BVH/01_01.bvh"
bcn="$models/X/BCN_Epileptic.X"
"$motionlod" export "$cmu" --unit-scale cmu --plugin gltf -o "$out/01_01.glb" --quiet >/dev/null
"$motionlod" export "$bcn" --plugin gltf -o "$out/BCN.glb" --quiet >/dev/null
"$motionlod" export "$bcn" --plugin gltf -o "$out/BCN_split.glb" --option split_levels=true --quiet >/dev/null
cmu_joints=$(joints "$out/01_01.glb")
bcn_joints=$(joints "$out/BCN.glb")
expect "$out/01_01.glb" 1 "$cmu_joints" 0 4 0
# a combined file: every level present, one visible (MSFT_lod applied by the project's add-on)
expect "$out/BCN.glb" 1 "$bcn_joints" 4 4 1
grep -q '^mesh: BCN_Epileptic_LOD0 .* visible$' "$out/BCN.glb.blender.txt" || fail "BCN.glb: LOD0 is not the visible mesh"
for level in 1 2 3; do
  grep -q "^mesh: BCN_Epileptic_LOD$level .* hidden (MSFT_lod level $level)\$" "$out/BCN.glb.blender.txt" ||
    fail "BCN.glb: LOD$level is not present and hidden"
done
for level in 0 1 2 3; do
  expect "$out/BCN_split_LOD$level.glb" 1 "$bcn_joints" 1 1 1
done
# the actions keep the source's frames: 120 fps, 2752 frames (0-2751) for CMU 01_01
grep -q '^fps: 120 ' "$out/01_01.glb.blender.txt" || fail "01_01.glb: Blender's scene was not set to 120 fps"
grep -q '^action: .* frames=0-2751$' "$out/01_01.glb.blender.txt" || fail "01_01.glb: no action spans frames 0-2751"
[ "$failures" -eq 0 ] || exit 1
echo "every export imported into Blender as expected"
