#!/bin/sh
# Imports a glTF file into Godot 3.2's editor headless (under Xvfb) and prints what Godot made
# of it:
#     scripts/check-godot.sh FILE.glb|FILE.gltf
#     fps: 30 (from the glTF's animation extras: 30)
#     skeleton: Skeleton bones=54
#     mesh: BCN_Epileptic_LOD0 surfaces=3 skeleton=Skeleton visible
#     mesh: BCN_Epileptic_LOD1 surfaces=3 skeleton=Skeleton hidden (MSFT_lod level 1)
#     animation: Take 001_LOD0 length=3.3
#     summary: skeletons=1 bones=54 meshes=4 animations=4 visible_meshes=1 visible_surfaces=3
# (a mesh's surfaces are its glTF primitives, one per character part). Exit 0 when Godot
# imported the file, 1 when it failed, 77 when there is no Godot 3 or no Xvfb
# (GODOT=/path/to/godot3 picks one; default: `godot3` on PATH, Debian's godot3 3.2.3).
#
# The file is copied into a throwaway project whose .import file sets the scene's import
# script (nodes/custom_script) to scripts/godot/motionlod_msft_lod.gd, the project's
# EditorScenePostImport script: Godot 3.2 imports every node of a glTF, the coarser levels
# that only MSFT_lod names included, knows no MSFT_lod and shows them all; the script hides
# the coarser levels (present, visible = false, metadata MSFT_lod_level). The .import file
# also sets animation/fps to the clips' frame rate (animation extras "fps"): Godot 3.2
# resamples every track at that rate, 15 fps unless told. Then
# `godot3 --path DIR -e --quit` imports it (the editor's first scan) and a GDScript run
# (`-s`) loads the imported scene and lists it. The editor's settings and caches go to a
# temporary directory (XDG_*), not to ~/.config/godot. docs/user-guide.md, "Godot", says
# how to do the same in Godot's editor.
set -eu
if [ $# -ne 1 ]; then
  echo "usage: $0 FILE.glb|FILE.gltf" >&2
  exit 2
fi
file=$1
if [ ! -f "$file" ]; then
  echo "error: $file: no such file" >&2
  exit 2
fi
case "$file" in
  *.glb | *.GLB) ext=glb ;;
  *.gltf | *.GLTF) ext=gltf ;;
  *)
    echo "error: $file: not a .glb or .gltf" >&2
    exit 2
    ;;
esac
godot=${GODOT:-godot3}
if ! command -v "$godot" >/dev/null 2>&1; then
  echo "skipped: no Godot 3 ($godot not found; apt install godot3)" >&2
  exit 77
fi
if ! command -v xvfb-run >/dev/null 2>&1; then
  echo "skipped: no xvfb-run (Godot 3's editor needs a display; apt install xvfb xauth)" >&2
  exit 77
fi
script_dir=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d "${TMPDIR:-/tmp}/check-godot.XXXXXX")
trap 'rm -rf "$work"' EXIT
project="$work/project"
mkdir -p "$project" "$work/xdg/config" "$work/xdg/data" "$work/xdg/cache"
XDG_CONFIG_HOME="$work/xdg/config" XDG_DATA_HOME="$work/xdg/data" XDG_CACHE_HOME="$work/xdg/cache"
export XDG_CONFIG_HOME XDG_DATA_HOME XDG_CACHE_HOME

cat >"$project/project.godot" <<'EOF'
config_version=4

[application]

config/name="motionlod check-godot"
EOF
cp "$file" "$project/model.$ext"
# The clips' frame rate (animation extras "fps", docs/gltf-extension.md), for the import's
# animation/fps; a .gltf's buffers and images named by relative path travel with it.
fps=$(python3 - "$file" "$project" <<'PYTHON'
import json, os, shutil, struct, sys
from urllib.parse import unquote
source, project = sys.argv[1], sys.argv[2]
with open(source, "rb") as f:
    data = f.read()
glb = data[:4] == b"glTF"
gltf = json.loads(data[20:20 + struct.unpack_from("<I", data, 12)[0]] if glb else data)
if not glb:
    for item in gltf.get("buffers", []) + gltf.get("images", []):
        uri = item.get("uri", "")
        if uri and not uri.startswith("data:") and "://" not in uri:
            target = os.path.join(project, unquote(uri))
            os.makedirs(os.path.dirname(target), exist_ok=True)
            shutil.copyfile(os.path.join(os.path.dirname(source), unquote(uri)), target)
fps = [(a.get("extras") or {}).get("fps") for a in gltf.get("animations", [])]
fps = [f for f in fps if isinstance(f, (int, float)) and f > 0]
print("%g" % fps[0] if fps else "")
PYTHON
)
cp "$script_dir/godot/motionlod_msft_lod.gd" "$project/motionlod_msft_lod.gd"
cat >"$project/model.$ext.import" <<'EOF'
[remap]

importer="scene"

[params]

nodes/custom_script="res://motionlod_msft_lod.gd"
EOF
if [ -n "$fps" ]; then
  # Godot 3.2 resamples every animation track at the import's animation/fps (15 by default,
  # a whole number): at the clips' own rate the samples fall on the source's frames
  godot_fps=$(awk -v fps="$fps" 'BEGIN { printf "%d", fps + 0.5 }')
  echo "animation/fps=$godot_fps" >>"$project/model.$ext.import"
  echo "fps: $godot_fps (from the glTF's animation extras: $fps)"
fi

cat >"$project/check_godot.gd" <<EOF
extends SceneTree

var meshes = 0
var visible_meshes = 0
var visible_surfaces = 0
var skeletons = 0
var bones = 0
var animations = 0

func _list(node):
	if node is Skeleton:
		skeletons += 1
		bones += node.get_bone_count()
		print("skeleton: %s bones=%d" % [node.name, node.get_bone_count()])
	elif node is MeshInstance:
		meshes += 1
		var surfaces = node.mesh.get_surface_count() if node.mesh else 0
		var skeleton = node.get_node_or_null(node.skeleton)
		var shown = node.is_visible_in_tree()
		var state = "visible"
		if shown:
			visible_meshes += 1
			visible_surfaces += surfaces
		else:
			state = "hidden (MSFT_lod level %s)" % (str(node.get_meta("MSFT_lod_level")) if node.has_meta("MSFT_lod_level") else "?")
		print("mesh: %s surfaces=%d skeleton=%s %s" % [node.name, surfaces, skeleton.name if skeleton else "none", state])
	elif node is AnimationPlayer:
		for name in node.get_animation_list():
			animations += 1
			print("animation: %s length=%s" % [name, str(node.get_animation(name).length)])
	for child in node.get_children():
		_list(child)

func _init():
	var scene = load("res://model.$ext")
	if scene == null:
		print("error: Godot did not import model.$ext")
		quit(1)
		return
	var root = scene.instance()
	get_root().add_child(root)
	_list(root)
	print("summary: skeletons=%d bones=%d meshes=%d animations=%d visible_meshes=%d visible_surfaces=%d" %
		[skeletons, bones, meshes, animations, visible_meshes, visible_surfaces])
	quit(0)
EOF

# The editor's first scan imports the file (.import/model.EXT-<md5>.md5 is written when it
# is done). Godot 3.2.3 now and then crashes on its way out after the import (signal 11,
# more often under load); what counts is whether the import was written: the editor is
# run again (up to three times) only when it was not.
imported() { ls "$project/.import/model.$ext-"*.md5 >/dev/null 2>&1; }
tries=0
while ! imported && [ $tries -lt 3 ]; do
  tries=$((tries + 1))
  timeout 300 xvfb-run -a "$godot" --path "$project" -e --quit >"$work/import.log" 2>&1 || true
done
if ! imported; then
  grep -v -e 'free_static' -e 'memory\.cpp' "$work/import.log" >&2 || true
  echo "error: $file: Godot did not import it ($tries tries)" >&2
  exit 1
fi
if timeout 300 xvfb-run -a "$godot" --path "$project" --no-window -s check_godot.gd >"$work/check.log" 2>&1 &&
  grep -E '^(skeleton|mesh|animation|summary): ' "$work/check.log" && grep -q '^summary: ' "$work/check.log"; then
  exit 0
fi
grep -v -e 'free_static' -e 'memory\.cpp' "$work/import.log" "$work/check.log" >&2 || true
exit 1
