#!/bin/sh
# Imports a file into Blender headless (no window) and prints what Blender made of it:
#     scripts/check-blender.sh FILE.glb|FILE.gltf|FILE.fbx
#     fps: 120 (from the glTF's animation extras)
#     armature: 01_01_skin bones=38
#     mesh: BCN_Epileptic_LOD0 vertices=3014 armature=... visible
#     mesh: BCN_Epileptic_LOD1 vertices=1574 armature=... hidden (MSFT_lod level 1)
#     action: 01_01_LOD0 frames=0-2751
#     summary: armatures=1 bones=38 meshes=0 actions=4 empties=0 visible_meshes=0
# Exit 0 when Blender imported the file, 1 when it failed, 77 when there is no Blender
# (BLENDER=/path/to/blender picks one; default: `blender` on PATH).
#
# Debian 12's Blender 3.4.1 cannot import glTF as installed: its importer needs numpy
# (apt install python3-numpy) and then fails on `np.bool`, which numpy 1.24 removed
# (Blender 3.5 fixed it upstream). This script puts `numpy.bool = bool` back before it
# imports, and sets the scene's frame rate to the glTF's (animation extras "fps",
# docs/gltf-extension.md) so that keys land on Blender's frames. Blender 3.4 shows every node
# of a glTF whatever its scene and knows no MSFT_lod: the script enables the project's add-on
# scripts/blender/motionlod_msft_lod.py, which hides the coarser levels MSFT_lod names (present,
# hidden), and prints which meshes are visible. docs/user-guide.md says how to do the same in
# Blender's window.
set -eu
if [ $# -ne 1 ]; then
  echo "usage: $0 FILE.glb|FILE.gltf|FILE.fbx" >&2
  exit 2
fi
file=$1
if [ ! -f "$file" ]; then
  echo "error: $file: no such file" >&2
  exit 2
fi
blender=${BLENDER:-blender}
if ! command -v "$blender" >/dev/null 2>&1; then
  echo "skipped: no Blender ($blender not found)" >&2
  exit 77
fi
script=$(mktemp "${TMPDIR:-/tmp}/check-blender.XXXXXX.py")
log=$(mktemp "${TMPDIR:-/tmp}/check-blender.XXXXXX.log")
trap 'rm -f "$script" "$log"' EXIT
cat >"$script" <<'PYTHON'
import json, os, struct, sys
import bpy

path = sys.argv[sys.argv.index("--") + 1]
try:
    import numpy
    if not hasattr(numpy, "bool"):
        numpy.bool = bool  # Blender 3.4's glTF importer uses np.bool (gone in numpy 1.24)
except ImportError:
    pass  # the glTF importer will say that numpy is missing

def gltf_json(path):
    with open(path, "rb") as f:
        data = f.read()
    if data[:4] == b"glTF":
        length, = struct.unpack_from("<I", data, 12)
        return json.loads(data[20:20 + length])
    return json.loads(data)

bpy.ops.wm.read_factory_settings(use_empty=True)
# MSFT_lod on import (scripts/blender/motionlod_msft_lod.py): the coarser levels present, hidden
import addon_utils
sys.path.insert(0, os.environ["MLOD_BLENDER_ADDONS"])
addon_utils.enable("motionlod_msft_lod", default_set=True)
scene = bpy.context.scene
ext = os.path.splitext(path)[1].lower()
if ext in (".glb", ".gltf"):
    fps = None
    for animation in gltf_json(path).get("animations", []):
        fps = fps or (animation.get("extras") or {}).get("fps")
    if fps:
        scene.render.fps = max(1, round(fps))
        scene.render.fps_base = scene.render.fps / fps
        print("fps: %g (from the glTF's animation extras)" % fps)
    result = bpy.ops.import_scene.gltf(filepath=path)
elif ext == ".fbx":
    result = bpy.ops.import_scene.fbx(filepath=path)
else:
    print("error: %s: not a .glb, .gltf or .fbx" % path)
    sys.exit(2)
if "FINISHED" not in result:
    print("error: %s: Blender's importer returned %s" % (path, result))
    sys.exit(1)
armatures = [o for o in bpy.data.objects if o.type == "ARMATURE"]
meshes = [o for o in bpy.data.objects if o.type == "MESH"]
bones = 0
for o in armatures:
    bones += len(o.data.bones)
    print("armature: %s bones=%d" % (o.name, len(o.data.bones)))
visible = 0
for o in meshes:
    parent = o.find_armature()
    shown = o.visible_get() and not o.hide_render
    visible += 1 if shown else 0
    print("mesh: %s vertices=%d armature=%s %s" % (o.name, len(o.data.vertices), parent.name if parent else "none",
                                                   "visible" if shown else "hidden (MSFT_lod level %s)" % o.get("MSFT_lod_level", "?")))
empties = [o for o in bpy.data.objects if o.type == "EMPTY"]
if empties:
    print("empties: %d" % len(empties))
for a in bpy.data.actions:
    print("action: %s frames=%g-%g" % (a.name, a.frame_range[0], a.frame_range[1]))
print("summary: armatures=%d bones=%d meshes=%d actions=%d empties=%d visible_meshes=%d" %
      (len(armatures), bones, len(meshes), len(bpy.data.actions), len(empties), visible))
sys.stdout.flush()
os._exit(0)  # skip Blender's exit handlers (slow, and noisy without a display)
PYTHON
MLOD_BLENDER_ADDONS=$(cd "$(dirname "$0")/blender" && pwd)
export MLOD_BLENDER_ADDONS
if "$blender" --background --factory-startup --python-exit-code 1 --python "$script" -- "$file" >"$log" 2>&1; then
  grep -E '^(fps|armature|mesh|empties|action|summary): ' "$log"
  grep -q '^summary: ' "$log" && exit 0
fi
cat "$log" >&2
exit 1
