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


func _enter_tree():
	for type in TYPES:
		add_custom_type(type[0], type[1], load(type[2]), load(type[3]))


func _exit_tree():
	for type in TYPES:
		remove_custom_type(type[0])
