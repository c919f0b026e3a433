# The addon in the Godot 3.2 editor, headless (scripts/godot-check copies this plugin into a
# project holding only the addon, as addons/crowdgaze_check, enables it after the crowdgaze
# plugin and runs `godot3-server --editor`): the crowdgaze plugin is enabled and in the editor's tree; the
# addon's nodes, in the editor's tree (tool mode), give the configuration warnings and the
# mapping report, join no crowd, do not process and write no bone (their controls set in
# the editor too); the bone pickers in a
# character's inspector write bone_map, undoably. Prints "CROWDGAZE EDITOR
# PASSED" (or FAILED) and quits the editor.
tool
extends EditorPlugin

const CrowdScript = preload("res://addons/crowdgaze/CrowdGaze.gdns")
const CharacterScript = preload("res://addons/crowdgaze/CrowdGazeCharacter.gdns")
const TargetScript = preload("res://addons/crowdgaze/GazeTarget.gdns")

var failures = []
var scene


func expect(condition, what):
	if not condition:
		failures.append(what)


func _enter_tree():
	call_deferred("run")


func skeleton_of(names):
	var skeleton = Skeleton.new()
	skeleton.name = "Skeleton"
	var height = 0.9
	for name in names:
		var bone = skeleton.get_bone_count()
		skeleton.add_bone(name)
		if bone > 0:
			skeleton.set_bone_parent(bone, bone - 1)
		skeleton.set_bone_rest(bone, Transform(Basis(), Vector3(0, height, 0)))
		height = 0.15
	return skeleton


func character(name, names):
	var root = Spatial.new()
	root.name = name
	var skeleton = skeleton_of(names)
	root.add_child(skeleton)
	var gaze = CharacterScript.new()
	gaze.name = "Gaze"
	skeleton.add_child(gaze)
	scene.add_child(root)
	return gaze


func run():
	expect(Engine.editor_hint, "not in the editor")
	expect(get_editor_interface().is_plugin_enabled("crowdgaze"), "the crowdgaze plugin is not enabled")
	var plugin = null
	for node in get_parent().get_children():
		if node is EditorPlugin and node.get_script() != null and node.get_script().resource_path == "res://addons/crowdgaze/plugin.gd":
			plugin = node
	expect(plugin != null, "plugin.gd is not in the editor's tree")
	var inspector = plugin.bone_inspector if plugin != null else null
	expect(inspector != null, "the plugin has no bone inspector")
	# A scene in the editor's tree, as the edited scene is.
	scene = Spatial.new()
	scene.name = "CrowdgazeEditorCheck"
	add_child(scene)
	# No CrowdGaze yet: the character and the target say so.
	var alone = character("Alone", ["Hips", "Spine", "Neck", "Head"])
	var warning = alone._get_configuration_warning()
	expect(warning.find("No CrowdGaze node in this scene") >= 0, "no warning about the missing crowd: " + warning)
	var crowd = CrowdScript.new()
	crowd.name = "CrowdGaze"
	scene.add_child(crowd)
	expect(not crowd.is_processing(), "the crowd processes in the editor")
	expect(crowd.process_priority == 0, "the crowd changed its process_priority in the editor (saved with the scene)")
	expect(crowd._get_configuration_warning() == "", "a default crowd warns: " + crowd._get_configuration_warning())
	warning = alone._get_configuration_warning()
	expect(warning.find("The gaze chain has no eyes bones") >= 0, "no warning about the missing eyes: " + warning)
	expect(warning.find("No CrowdGaze") < 0, "the crowd is still missing: " + warning)
	var report = alone.mapping_report
	expect(report.begins_with("gaze chain of "), "the mapping report: " + report)
	expect(report.find("'Head' (by name)") >= 0, "the report names no head: " + report)
	# Mapped with the eyes: no warning.
	var whole = character("Whole", ["Hips", "Spine", "Neck", "Head", "LeftEye"])
	var skeleton = whole.get_parent()
	skeleton.add_bone("RightEye")
	skeleton.set_bone_parent(5, 3)
	skeleton.set_bone_rest(4, Transform(Basis(), Vector3(0.03, 0.06, 0.08)))
	skeleton.set_bone_rest(5, Transform(Basis(), Vector3(-0.03, 0.06, 0.08)))
	expect(whole._get_configuration_warning() == "", "a whole chain warns: " + whole._get_configuration_warning())
	# No head.
	var headless = character("Headless", ["Hips", "Spine", "Tail"])
	warning = headless._get_configuration_warning()
	expect(warning.begins_with("No head found: ") and warning.find("'Tail'") >= 0, "the headless skeleton's warning: " + warning)
	expect(headless.mapping_report.begins_with("no gaze chain: "), "the headless report: " + headless.mapping_report)
	# The bone pickers: picking Tail as the head writes Tail=head into bone_map (undoably).
	expect(inspector.can_handle(headless) and not inspector.can_handle(crowd), "the bone inspector's can_handle")
	var pickers = inspector.make_pickers(headless)
	var head = pickers.find_node("head", true, false)
	expect(head is OptionButton and head.get_item_count() == 4 and head.selected == 0, "the head picker lists (by name) and the 3 bones")
	head.select(3)
	head.emit_signal("item_selected", 3)
	pickers.free()
	expect(headless.bone_map == "Tail=head", "picking the head wrote bone_map = '%s'" % headless.bone_map)
	expect(headless.mapping_report.find("'Tail' (override)") >= 0, "bone_map did not change the report: " + headless.mapping_report)
	warning = headless._get_configuration_warning()
	expect(warning.find("No head") < 0 and warning.find("Tail=head") < 0, "the head is still missing: " + warning)
	get_undo_redo().undo()
	expect(headless.bone_map == "", "undo left bone_map = '%s'" % headless.bone_map)
	get_undo_redo().redo()
	expect(headless.bone_map == "Tail=head", "redo left bone_map = '%s'" % headless.bone_map)
	pickers = inspector.make_pickers(headless)
	expect(pickers.find_node("head", true, false).selected == 3, "the head picker does not show Tail")
	pickers.free()
	var Pickers = load("res://addons/crowdgaze/bone_inspector.gd")
	expect(Pickers.with_role("A=head, B=spine", "C", "head") == "B=spine,C=head", "with_role replaces a role")
	expect(Pickers.with_role("A=head,B=spine", "", "head") == "B=spine", "with_role clears a role")
	expect(Pickers.with_role("B=spine", "B", "head") == "B=head", "with_role moves a bone")
	# Not under a skeleton.
	var stray = CharacterScript.new()
	stray.name = "Stray"
	scene.add_child(stray)
	expect(stray._get_configuration_warning().begins_with("Not under a Skeleton"), "the stray's warning: " + stray._get_configuration_warning())
	# Mirrored.
	var mirrored = character("Mirrored", ["Hips", "Spine", "Neck", "Head"])
	mirrored.get_parent().get_parent().scale = Vector3(-1, 1, 1)
	warning = mirrored._get_configuration_warning()
	expect(warning.find("mirrored") >= 0, "the mirrored skeleton's warning: " + warning)
	# A target whose crowd path names another kind of node, with a NaN height.
	var target = TargetScript.new()
	target.name = "Lamp"
	target.crowd = NodePath("../Alone")
	target.look_at_height = NAN
	scene.add_child(target)
	warning = target._get_configuration_warning()
	expect(warning.find("look_at_height = NaN") >= 0 and warning.find("names a Spatial") >= 0 and warning.find("not a CrowdGaze") >= 0, "the target's warning: " + warning)
	# The controls set in the editor: kept as values, nothing fades, joins or is written, and
	# no error (a bad value is reported when the game runs; the run fails on any error).
	crowd.active = false
	crowd.influence = NAN
	crowd.influence = 0.5
	crowd.influence_fade_time = 2.0
	crowd.eyes_only_angle = 10.0
	crowd.eyes_head_neck_angle = 25.0
	crowd.head_speed = 200.0
	whole.active = false
	whole.influence = 0.25
	whole.influence_fade_time = -1.0
	whole.talking = true
	whole.attention_fraction = 0.4
	whole.attention_model = 1
	whole.max_head_turn = 60.0
	whole.max_eye_angle = 30.0
	whole.eyelid_mesh = NodePath("Nowhere")
	whole.eyelid_shapes = "wink"
	expect(not crowd.active and crowd.influence == 0.5 and crowd.head_speed == 200.0, "the crowd's controls were not kept in the editor")
	expect(not whole.active and whole.influence == 0.25 and whole.attention_model == 1 and whole.eyelid_shapes == "wink", "the character's controls were not kept in the editor")
	expect(crowd.get_character_influence(whole) == 0.0 and crowd.get_conversation(whole) == -1, "the character has an influence in the editor")
	expect(whole._get_configuration_warning() == "", "the controls made the whole chain warn: " + whole._get_configuration_warning())
	expect(crowd._get_configuration_warning() == "", "the controls made the crowd warn: " + crowd._get_configuration_warning())
	# A bad crowd setting.
	crowd.max_characters = -5
	expect(crowd._get_configuration_warning().find("max_characters = -5") >= 0, "the crowd's warning: " + crowd._get_configuration_warning())
	# Nothing joined, nothing was written, for a few frames.
	for _k in range(5):
		yield(get_tree(), "idle_frame")
	expect(crowd.get_character_count() == 0 and crowd.get_target_count() == 0, "nodes joined the crowd in the editor")
	for bone in range(skeleton.get_bone_count()):
		expect(skeleton.get_bone_pose(bone) == Transform(), "bone %d was written in the editor" % bone)
	scene.free()
	for failure in failures:
		print("CROWDGAZE EDITOR FAILURE " + failure)
	if failures.empty():
		print("CROWDGAZE EDITOR PASSED")
	else:
		print("CROWDGAZE EDITOR FAILED")
	get_tree().quit()
