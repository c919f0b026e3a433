# Rigs the addon must map, headless (scripts/godot-check runs res://rigs.tscn as it runs
# bad_input.tscn): eyes that hang from the head through a facial bone (as Character
# Creator's CC_Base_FacialBone and MetaHuman's FACIAL_C_FacialRoot), with a rest rotation
# on the facial bone and an animation turning it every frame. The character is made to
# look at a target; once its gaze holds, each eye bone's global forward (its rest forward,
# the skeleton's +Z, carried by the eye's global pose) must point at the target within 2
# degrees, and the facial bone must keep the animation's pose (the addon reads it, never
# writes it). Prints "CROWDGAZE RIGS PASSED" (or FAILED) and quits with 0 (or 1).
extends Spatial

const CharacterScript = preload("res://addons/crowdgaze/CrowdGazeCharacter.gdns")
const TargetScript = preload("res://addons/crowdgaze/GazeTarget.gdns")
const Check = preload("res://check.gd")   # its rest_global
const TOLERANCE_DEGREES = 2.0

# name, parent, rest position relative to the parent (metres, Y up, facing +Z).
const FACIAL_RIG = [
	["Hips", "", Vector3(0, 0.95, 0)],
	["Spine", "Hips", Vector3(0, 0.1, 0)],
	["Chest", "Spine", Vector3(0, 0.25, 0.02)],
	["Neck", "Chest", Vector3(0, 0.2, 0)],
	["Head", "Neck", Vector3(0, 0.08, 0)],
	["FacialRoot", "Head", Vector3(0, 0.01, 0.01)],
	["LeftEye", "FacialRoot", Vector3(0.032, 0.05, 0.075)],
	["RightEye", "FacialRoot", Vector3(-0.032, 0.05, 0.075)],
	["LeftUpLeg", "Hips", Vector3(0.1, -0.05, 0)],
	["RightUpLeg", "Hips", Vector3(-0.1, -0.05, 0)],
]

var frame = 0
var failures = []
var skeleton
var gaze
var target
var facial = -1
var facial_pose = Transform()
var held = 0
var worst = 0.0

onready var crowd = $CrowdGaze


func expect(condition, what):
	if not condition:
		failures.append("frame %d: %s" % [frame, what])


func _ready():
	var root = Spatial.new()
	root.name = "Face"
	skeleton = Skeleton.new()
	skeleton.name = "Skeleton"
	for entry in FACIAL_RIG:
		var bone = skeleton.get_bone_count()
		skeleton.add_bone(entry[0])
		if entry[1] != "":
			skeleton.set_bone_parent(bone, skeleton.find_bone(entry[1]))
		var rest = Transform(Basis(), entry[2])
		if entry[0] == "FacialRoot":
			# Face rigs often turn the facial bone at rest.
			rest.basis = Basis(Vector3(0.3, 1, 0.2).normalized(), 0.4)
		skeleton.set_bone_rest(bone, rest)
	facial = skeleton.find_bone("FacialRoot")
	root.add_child(skeleton)
	gaze = CharacterScript.new()
	gaze.name = "Gaze"
	skeleton.add_child(gaze)
	root.transform = Transform(Basis(Vector3.UP, 0.5), Vector3(1, 0, -1))
	add_child(root)
	target = TargetScript.new()
	target.name = "Lamp"
	target.translation = Vector3(2.5, 0.4, 1.5)
	target.look_at_height = 1.2
	add_child(target)
	expect(crowd.get_character_count() == 1, "the facial rig was refused")
	var chain = crowd.get_chain_bones(gaze)
	expect(chain.size() == 6, "the chain has %d bones, not 6" % chain.size())
	expect(not (facial in chain), "the facial bone is a chain joint")
	expect(gaze.mapping_report.find("through 'FacialRoot'") >= 0, "the report does not note the facial bone: " + gaze.mapping_report)
	expect(crowd.set_gaze_target(gaze, target), "set_gaze_target")


func check_eyes():
	var point = target.global_transform.origin + Vector3.UP * target.look_at_height
	for name in ["LeftEye", "RightEye"]:
		var eye = skeleton.find_bone(name)
		var forward = Check.rest_global(skeleton, eye).basis.inverse().xform(Vector3.BACK)
		var pose = skeleton.global_transform * skeleton.get_bone_global_pose(eye)
		var error = rad2deg(pose.basis.xform(forward).angle_to(point - pose.origin))
		worst = max(worst, error)
		expect(error < TOLERANCE_DEGREES, "%s is %.2f degrees off the target" % [name, error])


func _process(_delta):
	frame += 1
	if frame > 1:
		# The last frame's gaze, as the addon wrote it.
		expect(skeleton.get_bone_pose(facial) == facial_pose, "the facial bone's pose was written")
		if crowd.is_holding(gaze):
			held += 1
			check_eyes()
	# The face rig's animation: the facial bone turns under the gaze.
	facial_pose = Transform(Basis(Vector3.RIGHT, 0.08 * sin(frame * 0.2)), Vector3.ZERO)
	skeleton.set_bone_pose(facial, facial_pose)
	if frame == 90:
		expect(held > 20, "the gaze held for %d frames only" % held)
		print("CROWDGAZE RIGS eyes under a facial bone: held %d frames, worst %.3f degrees" % [held, worst])
		for failure in failures.slice(0, 19):
			print("CROWDGAZE RIGS FAILURE " + failure)
		if failures.empty():
			print("CROWDGAZE RIGS PASSED")
			get_tree().quit(0)
		else:
			print("CROWDGAZE RIGS FAILED")
			get_tree().quit(1)
