#!/bin/sh
# godot_gltf_test.sh MOTIONLOD CHECK_GODOT MODELS OUT_DIR
# Exports two skinned characters, BCN_Epileptic (3 parts, 1 clip) and Testwuson (1 part,
# 3 clips), to combined glTF files (every level in one file; BCN also as .gltf), imports each
# into Godot 3.2's editor headless (check-godot.sh, with the project's post-import script
# scripts/godot/motionlod_msft_lod.gd) and checks: one skeleton with every joint as a bone,
# every level's mesh present, exactly one of them visible, showing each character part once
# (its surfaces), the coarser levels hidden with their MSFT_lod level, and one animation per
# level and clip, imported at the clips' frame rate. Exit 77 (ctest: skipped) when there is
# no Godot 3 or no xvfb-run.
set -eu
motionlod=$1 check=$2 models=$3 out=$4
godot=${GODOT:-}
if [ -z "$godot" ] || [ "${godot%NOTFOUND}" != "$godot" ] || ! command -v "$godot" >/dev/null 2>&1; then
  echo "skipped: Godot 3 is not installed (apt install godot3)"
  exit 77
fi
if ! command -v xvfb-run >/dev/null 2>&1; then
  echo "skipped: xvfb-run is not installed (apt install xvfb xauth)"
  exit 77
fi
export GODOT="$godot"
rm -rf "$out"
mkdir -p "$out"
failures=0
fail() {
  echo "FAIL: $*"
  failures=$((failures + 1))
}
# What the file itself says: "NAME LEVELS PARTS ANIMATIONS FPS" (the node with MSFT_lod,
# its levels with it, its mesh's primitives = character parts, the glTF's animations, their
# frame rate rounded as Godot's animation/fps takes it)
describe() {
  python3 - "$1" <<'PYTHON'
import json, struct, sys
with open(sys.argv[1], "rb") as f:
    data = f.read()
gltf = json.loads(data[20:20 + struct.unpack_from("<I", data, 12)[0]] if data[:4] == b"glTF" else data)
hosts = [n for n in gltf["nodes"] if "MSFT_lod" in n.get("extensions", {})]
if len(hosts) != 1 or "mesh" not in hosts[0]:
    sys.exit("%s: %d nodes with MSFT_lod, expected one mesh node" % (sys.argv[1], len(hosts)))
host = hosts[0]
name = host["name"].rsplit("_LOD", 1)[0]
print(name, 1 + len(host["extensions"]["MSFT_lod"]["ids"]), len(gltf["meshes"][host["mesh"]]["primitives"]),
      len(gltf.get("animations", [])), int(gltf["animations"][0]["extras"]["fps"] + 0.5))
PYTHON
}
joints() { "$motionlod" info "$1" --json | python3 -c 'import json,sys; print(len(json.load(sys.stdin)["joints"]))'; }
# check FILE: every level present, one visible with every part, the others hidden
check() {
  file=$1
  info=$(describe "$file") || { fail "$file: not a combined file"; return; }
  set -- $info
  name=$1 levels=$2 parts=$3 animations=$4 fps=$5
  bones=$(joints "$file")
  [ "$levels" -ge 2 ] || fail "$file: $levels level(s), a combined file with several was expected"
  summary=$("$check" "$file" 2>"$file.godot.err" | tee "$file.godot.txt" | grep '^summary: ') ||
    { fail "$file: Godot did not import it"; cat "$file.godot.txt" "$file.godot.err"; return; }
  want="summary: skeletons=1 bones=$bones meshes=$levels animations=$animations visible_meshes=1 visible_surfaces=$parts"
  case "$summary" in
    "$want") echo "ok: $file: $summary" ;;
    *) fail "$file: $summary, expected $want"; cat "$file.godot.txt" ;;
  esac
  grep -q "^mesh: ${name}_LOD0 surfaces=$parts skeleton=Skeleton visible\$" "$file.godot.txt" ||
    fail "$file: ${name}_LOD0 is not the visible mesh with its $parts part(s)"
  grep -q "^fps: $fps " "$file.godot.txt" || fail "$file: Godot's animation/fps was not set to the clips' $fps fps"
  level=1
  while [ "$level" -lt "$levels" ]; do
    grep -q "^mesh: ${name}_LOD$level surfaces=$parts skeleton=Skeleton hidden (MSFT_lod level $level)\$" "$file.godot.txt" ||
      fail "$file: ${name}_LOD$level is not present and hidden"
    level=$((level + 1))
  done
}

bcn="$models/X/BCN_Epileptic.X"
wuson="$models/X/Testwuson.X"
"$motionlod" export "$bcn" --plugin gltf -o "$out/BCN.glb" --quiet >/dev/null
"$motionlod" export "$bcn" --plugin gltf -o "$out/BCN.gltf" --quiet >/dev/null
"$motionlod" export "$wuson" --plugin gltf -o "$out/Testwuson.glb" --quiet >/dev/null
check "$out/BCN.glb"
check "$out/BCN.gltf"
check "$out/Testwuson.glb"
[ "$failures" -eq 0 ] || exit 1
echo "every combined export imported into Godot 3 with one visible level and every level present"
