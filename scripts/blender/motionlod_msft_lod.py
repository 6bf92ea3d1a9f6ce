# Motion LOD Studio: MSFT_lod on Blender's glTF import (docs/user-guide.md, "Blender").
#
# Blender 3.4's glTF importer (io_scene_gltf2) makes an object of every node of the file,
# whichever scene holds it (init_vnodes() walks gltf.data.nodes, not the scenes), links them
# all into the active collection and knows neither MSFT_lod nor any visibility: a file with
# every level shows all the level meshes on top of each other. No glTF construct changes
# that (a node outside the default scene, a second scene, extras: all imported, all shown).
#
# This add-on applies MSFT_lod on import, through the importer's user-extension hook: the
# nodes a node's MSFT_lod names (the coarser levels) stay in the scene, hidden in the
# viewport and in renders, so one level shows, as in a reader that knows no MSFT_lod; each
# keeps its level in the custom property "MSFT_lod_level" (1, 2 ...). Install it with
# Edit > Preferences > Add-ons > Install... and enable it; scripts/check-blender.sh enables
# it for its headless imports.

bl_info = {
    "name": "Motion LOD: MSFT_lod levels on glTF import",
    "author": "Motion LOD Studio",
    "version": (1, 0, 0),
    "blender": (3, 4, 0),
    "location": "File > Import > glTF 2.0",
    "description": "Hides the coarser levels that a glTF node's MSFT_lod names, keeping them in the scene",
    "category": "Import-Export",
}


class glTF2ImportUserExtension:
    def gather_import_scene_after_nodes_hook(self, gltf_scene, blender_scene, gltf):
        for node in gltf.data.nodes or []:
            lod = (node.extensions or {}).get("MSFT_lod") or {}
            for level, index in enumerate(lod.get("ids") or [], 1):
                vnode = gltf.vnodes.get(index) if isinstance(index, int) else None
                obj = vnode.blender_object if vnode is not None else None
                if obj is None:
                    continue
                obj["MSFT_lod_level"] = level
                obj.hide_render = True
                obj.hide_set(True)


def register():
    pass


def unregister():
    pass
