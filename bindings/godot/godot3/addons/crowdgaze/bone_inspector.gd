# Bone pickers in a CrowdGazeCharacter's inspector (Godot 3.2; added by plugin.gd): one list
# per role a single bone plays (head, left eye, right eye, the bone the chain hangs from),
# offering "(by name)" and every bone of the parent Skeleton. Picking a bone writes the
# override into bone_map (undoable), which the addon maps at once; mapping_report, below,
# shows the result. Spine and neck bones (several each) are mapped in bone_map by hand.
tool
extends EditorInspectorPlugin

const CHARACTER_SCRIPT = "res://addons/crowdgaze/CrowdGazeCharacter.gdns"
const ROLES = [["head", "Head"], ["left_eye", "Left eye"], ["right_eye", "Right eye"], ["root", "Chain hangs from"]]
const BY_NAME = "(by name)"

var undo_redo = null   # the editor's UndoRedo (set by plugin.gd)


func can_handle(object):
	return object is Spatial and object.get_script() != null and object.get_script().resource_path == CHARACTER_SCRIPT


func parse_begin(object):
	add_custom_control(make_pickers(object))


# The pickers for `character`: a VBoxContainer holding, per role, an OptionButton named
# after the role.
func make_pickers(character):
	var box = VBoxContainer.new()
	box.name = "CrowdgazeBonePickers"
	var skeleton = character.get_parent()
	if not skeleton is Skeleton:
		var label = Label.new()
		label.text = "Bone pickers: put this node under a Skeleton"
		box.add_child(label)
		return box
	var chosen = overrides(character.bone_map)
	for role in ROLES:
		var row = HBoxContainer.new()
		var label = Label.new()
		label.text = role[1]
		label.size_flags_horizontal = Control.SIZE_EXPAND_FILL
		row.add_child(label)
		var picker = OptionButton.new()
		picker.name = role[0]
		picker.size_flags_horizontal = Control.SIZE_EXPAND_FILL
		picker.add_item(BY_NAME)
		for bone in range(skeleton.get_bone_count()):
			var name = skeleton.get_bone_name(bone)
			picker.add_item(name)
			if chosen.get(role[0], "") == name:
				picker.select(bone + 1)
		picker.connect("item_selected", self, "_on_picked", [character, picker, role[0]])
		row.add_child(picker)
		box.add_child(row)
	return box


func _on_picked(index, character, picker, role):
	var bone = "" if index == 0 else picker.get_item_text(index)
	var before = character.bone_map
	var after = with_role(before, bone, role)
	if after == before:
		return
	if undo_redo != null:
		undo_redo.create_action("Set %s of %s" % [role, character.name])
		undo_redo.add_do_property(character, "bone_map", after)
		undo_redo.add_undo_property(character, "bone_map", before)
		undo_redo.add_do_method(character, "property_list_changed_notify")
		undo_redo.add_undo_method(character, "property_list_changed_notify")
		undo_redo.commit_action()
	else:
		character.bone_map = after
		character.property_list_changed_notify()


# bone_map's overrides, role -> bone name (the last one for each role).
static func overrides(bone_map):
	var result = {}
	for entry in bone_map.split(",", false):
		var parts = entry.split("=")
		if parts.size() == 2:
			result[parts[1].strip_edges().to_lower()] = parts[0].strip_edges()
	return result


# bone_map with `role` given to `bone` ("" for none: the role is found by name again): the
# role's other overrides and the bone's own are dropped, the rest kept in order.
static func with_role(bone_map, bone, role):
	var entries = []
	for entry in bone_map.split(",", false):
		var parts = entry.split("=")
		if parts.size() == 2 and (parts[1].strip_edges().to_lower() == role or parts[0].strip_edges() == bone):
			continue
		entries.append(entry.strip_edges())
	if bone != "":
		entries.append("%s=%s" % [bone, role])
	return PoolStringArray(entries).join(",")
