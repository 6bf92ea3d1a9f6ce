# Motion LOD Studio: MSFT_lod on Godot 3.2's glTF import (docs/user-guide.md, "Godot").
#
# Godot 3.2's glTF importer makes a node of every node of the file, whichever scene holds
# it (the coarser levels, which only MSFT_lod names, come in too), knows no MSFT_lod, and
# shows every MeshInstance: a file with every level shows all the level meshes on top of
# each other. (GeometryInstance's lod_min_distance / lod_max_distance do nothing in 3.2.)
#
# This post-import script applies MSFT_lod: it reads the glTF's own JSON (a .gltf, or a
# .glb's JSON chunk), and the nodes that a node's MSFT_lod names (the coarser levels, in
# order) stay in the scene, hidden (visible = false), each with the metadata
# "MSFT_lod_level" (1, 2 ...), so one level shows: the finest. Use it as the scene's
# Import > Script (the .import file's nodes/custom_script), then Reimport;
# scripts/check-godot.sh does so for its headless imports.
tool
extends EditorScenePostImport


func post_import(scene):
	if not get_source_file().get_extension().to_lower() in ["gltf", "glb"]:
		return scene  # made a project's default: other formats pass through unchanged
	var gltf = _read_gltf_json(get_source_file())
	if typeof(gltf) != TYPE_DICTIONARY:
		push_warning("motionlod_msft_lod: %s: no glTF JSON read; nothing hidden" % get_source_file())
		return scene
	var nodes = gltf.get("nodes", [])
	for node in nodes:
		var extensions = node.get("extensions", {})
		if typeof(extensions) != TYPE_DICTIONARY or not extensions.has("MSFT_lod"):
			continue
		var ids = extensions["MSFT_lod"].get("ids", [])
		for level in range(ids.size()):
			var index = int(ids[level])
			if index < 0 or index >= nodes.size() or not nodes[index].has("name"):
				push_warning("motionlod_msft_lod: MSFT_lod names node %d, which has no name" % index)
				continue
			var found = _find(scene, String(nodes[index]["name"]))
			if found == null:
				push_warning("motionlod_msft_lod: no imported node %s (MSFT_lod level %d)" % [nodes[index]["name"], level + 1])
				continue
			found.set_meta("MSFT_lod_level", level + 1)
			found.visible = false
	return scene


# The imported node a glTF node became: Godot 3.2 names it after the glTF node.
func _find(node, name):
	if node.name == name and node is Spatial:
		return node
	for child in node.get_children():
		var found = _find(child, name)
		if found != null:
			return found
	return null


# The glTF's JSON: the file itself (.gltf) or a .glb's first chunk (type "JSON").
func _read_gltf_json(path):
	var file = File.new()
	if file.open(path, File.READ) != OK:
		return null
	var text = ""
	if file.get_len() >= 20 and file.get_32() == 0x46546C67:  # "glTF"
		file.get_32()  # version
		file.get_32()  # total length
		var length = file.get_32()
		if file.get_32() != 0x4E4F534A:  # "JSON"
			file.close()
			return null
		text = file.get_buffer(length).get_string_from_utf8()
	else:
		file.seek(0)
		text = file.get_buffer(file.get_len()).get_string_from_utf8()
	file.close()
	var parsed = JSON.parse(text)
	if parsed.error != OK:
		return null
	return parsed.result
