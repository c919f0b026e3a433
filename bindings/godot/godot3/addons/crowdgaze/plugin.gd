# crowdgaze's editor plugin for Godot 3.2 (enable it in Project Settings > Plugins): the
# addon's three nodes in the Create Node dialog, with their icons, and the bone pickers in
# a CrowdGazeCharacter's inspector (bone_inspector.gd). The nodes work without the plugin
# too (attach their .gdns scripts): it only adds them to the editor's dialogs.
tool
extends EditorPlugin

# Each custom type: name, the Godot class it extends, its script, its icon.
const TYPES = [
	["CrowdGaze", "Spatial", "res://addons/crowdgaze/CrowdGaze.gdns", "res://addons/crowdgaze/icons/crowd_gaze.svg"],
	["CrowdGazeCharacter", "Spatial", "res://addons/crowdgaze/CrowdGazeCharacter.gdns", "res://addons/crowdgaze/icons/crowd_gaze_character.svg"],
	["GazeTarget", "Spatial", "res://addons/crowdgaze/GazeTarget.gdns", "res://addons/crowdgaze/icons/gaze_target.svg"],
]


var bone_inspector = null   # the bone pickers (bone_inspector.gd)


func _enter_tree():
	for type in TYPES:
		add_custom_type(type[0], type[1], load(type[2]), load(type[3]))
	bone_inspector = load("res://addons/crowdgaze/bone_inspector.gd").new()
	bone_inspector.undo_redo = get_undo_redo()
	add_inspector_plugin(bone_inspector)


func _exit_tree():
	for type in TYPES:
		remove_custom_type(type[0])
	if bone_inspector != null:
		remove_inspector_plugin(bone_inspector)
		bone_inspector = null
