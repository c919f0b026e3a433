# The addon's controls and outputs, checked from Godot's side (scripts/godot-check runs
# res://controls.tscn as it runs cases.tscn): influence blends the animated pose (here the
# rest: nothing animates) towards the library's gaze, for a character and crowd-wide, at
# once and over a fade time; an inactive character's bones are left to the animation; lid
# bones and blink blend shapes follow the library's eyelids; a talking pair in conversation
# looks at each other; conversations are formed, read and ended; the looking signals come;
# joint limits and attention settings change live. Each error it provokes is announced
# with "EXPECT ERROR <text>"; it prints "CROWDGAZE CONTROLS PASSED" (or FAILED) and quits.
extends Spatial

const Builder = preload("res://lib/bvh_skeleton.gd")
const CharacterScript = preload("res://addons/crowdgaze/CrowdGazeCharacter.gdns")
const TOLERANCE = 1e-5
const CLOSED_LID = deg2rad(35.0)
const END = 420

var builder
var frame = 0
var failures = []
var fader
var lidded
var speaker
var listener
var mesh
var conversation = -1
var listener_on_speaker = 0
var listener_frames = 0
var blink_frames = 0
var shape_frames = 0
var started = 0
var stopped = 0
var held_pose

onready var crowd = $CrowdGaze


func expect(condition, what):
	if not condition:
		failures.append("frame %d: %s" % [frame, what])


func expect_error(text):
	print("EXPECT ERROR " + text)


# The angle between two rotations, precise near 0.
static func angle(a, b):
	var q = a.inverse() * b
	return 2.0 * atan2(Vector3(q.x, q.y, q.z).length(), abs(q.w))


func person(name, position, facing):
	var root = Spatial.new()
	root.name = name
	root.translation = position
	root.rotation.y = facing
	var skeleton = Skeleton.new()
	skeleton.name = "Skeleton"
	builder.build(skeleton)
	root.add_child(skeleton)
	var gaze = CharacterScript.new()
	gaze.name = "Gaze"
	skeleton.add_child(gaze)
	add_child(root)
	return gaze


# A mesh with ARKit's two blink shapes (one triangle; only the shapes' values matter).
func blink_mesh():
	var arrays = []
	arrays.resize(Mesh.ARRAY_MAX)
	arrays[Mesh.ARRAY_VERTEX] = PoolVector3Array([Vector3.ZERO, Vector3.RIGHT, Vector3.UP])
	var shape = []
	shape.resize(Mesh.ARRAY_MAX)
	shape[Mesh.ARRAY_VERTEX] = PoolVector3Array([Vector3.ZERO, Vector3.RIGHT, Vector3.FORWARD])
	var array_mesh = ArrayMesh.new()
	array_mesh.add_blend_shape("jawOpen")
	array_mesh.add_blend_shape("eyeBlinkLeft")
	array_mesh.add_blend_shape("eyeBlinkRight")
	array_mesh.add_surface_from_arrays(Mesh.PRIMITIVE_TRIANGLES, arrays, [shape, shape, shape])
	var instance = MeshInstance.new()
	instance.name = "Face"
	instance.mesh = array_mesh
	return instance


func _ready():
	builder = Builder.new()
	var error = builder.load_shared("bvh/zombie.bvh", 1.7)
	if error != "":
		failures.append(error)
		return
	builder.add_lids()
	crowd.influence_fade_time = 0.0
	crowd.connect("character_started_looking", self, "_on_started")
	crowd.connect("character_stopped_looking", self, "_on_stopped")


func _on_started(character, target):
	expect(character != null, "started looking without a character")
	started += 1


func _on_stopped(character, _target):
	expect(character != null, "stopped looking without a character")
	stopped += 1


# Each chain joint's pose (relative to its rest) against the library's rotation turned
# into a pose, at `share` of the way from the rest (the animated pose here): the largest
# angle between them, radians. The first joint is relative to the character frame, so it is
# left out (cases.gd and check.gd check it).
func blend_error(gaze, share):
	var skeleton = gaze.get_parent()
	var bones = crowd.get_chain_bones(gaze)
	var rotations = crowd.get_joint_rotations(gaze)
	if bones.size() < 3 or rotations.size() != bones.size():
		return INF
	var worst = 0.0
	for k in range(1, bones.size()):
		var rest = skeleton.get_bone_rest(bones[k]).basis.get_rotation_quat()
		var full = rest.inverse() * rotations[k]
		var expected = Quat().slerp(full, share)
		var pose = skeleton.get_bone_pose(bones[k]).basis.get_rotation_quat()
		worst = max(worst, angle(pose, expected))
	return worst


# The largest angle of any chain joint's pose from its rest (the animated pose here).
func rest_error(gaze):
	var skeleton = gaze.get_parent()
	var worst = 0.0
	for bone in crowd.get_chain_bones(gaze):
		worst = max(worst, angle(skeleton.get_bone_pose(bone).basis.get_rotation_quat(), Quat()))
	return worst


func check_eyelids():
	var lids = crowd.get_eyelids(lidded)
	var closure = lids.x
	if closure < 0.3:
		return
	blink_frames += 1
	# Lid bones: turned down by the lid angle (the pitch's share and the closure).
	var skeleton = lidded.get_parent()
	var expected = -lids.y + (CLOSED_LID + lids.y) * closure
	for name in ["eyelid_upper_l", "eyelid_upper_r"]:
		var pose = skeleton.get_bone_pose(skeleton.find_bone(name)).basis.get_rotation_quat()
		var turned = angle(pose, Quat())
		# Both lids take their own eye's pitch; get_eyelids gives their mean.
		expect(abs(turned - abs(expected)) < 0.02, "%s turned %f rad, the eyelids say %f" % [name, turned, expected])
	# Blend shapes: the closure, each eye's.
	for shape in ["blend_shapes/eyeBlinkLeft", "blend_shapes/eyeBlinkRight"]:
		var value = mesh.get(shape)
		expect(abs(value - closure) < 1e-3, "%s is %f, the closure %f" % [shape, value, closure])
	expect(mesh.get("blend_shapes/jawOpen") == 0.0, "a shape other than the blinks was set")
	shape_frames += 1


func _process(_delta):
	frame += 1
	if not failures.empty() and frame < END:
		frame = END
	if frame > 3 and frame < END - 2:
		check_eyelids()
		if conversation >= 0 and frame > 90:
			listener_frames += 1
			if crowd.get_gaze_target(listener) == speaker:
				listener_on_speaker += 1
	match frame:
		2:
			fader = person("Fader", Vector3(0, 0, 0), 0.0)
			fader.influence_fade_time = 0.0
			lidded = person("Lidded", Vector3(-3, 0, 0), 0.5)
			mesh = blink_mesh()
			lidded.add_child(mesh)
			lidded.eyelid_mesh = NodePath("Face")
			speaker = person("Speaker", Vector3(6, 0, 0), -PI / 2)
			listener = person("Listener", Vector3(4.8, 0, 0), PI / 2)
			expect(crowd.get_character_count() == 4, "4 characters joined, the crowd holds %d" % crowd.get_character_count())
			expect(crowd.set_gaze_target(fader, Vector3(2.5, 1.9, 1.5)), "a point to look at")
			var skeleton = lidded.get_parent()
			expect(skeleton.find_bone("eyelid_upper_l") >= 0, "the lidded skeleton has no lid bone")
		3:
			conversation = crowd.set_conversation([speaker, listener])
			expect(conversation >= 0, "no conversation was formed")
			expect(crowd.get_conversation(speaker) == conversation, "the speaker is not in the conversation")
			expect(crowd.get_conversation(listener) == conversation, "the listener is not in the conversation")
			expect(crowd.get_conversation(fader) == -1, "the fader is in a conversation")
			speaker.talking = true
			expect_error("/root/Controls/CrowdGaze: CrowdGaze.set_conversation: invalid argument: character")
			expect(crowd.set_conversation([listener, fader]) == -1, "a listener in two conversations")
		40:
			expect(crowd.get_character_influence(fader) == 1.0, "full influence is %f" % crowd.get_character_influence(fader))
			var error = blend_error(fader, 1.0)
			expect(error < TOLERANCE, "at influence 1 the poses are %f rad from the gaze" % error)
			expect(rest_error(fader) > 0.05, "the gaze turned nothing")
			fader.influence = 0.5
		41:
			expect(crowd.get_character_influence(fader) == 0.5, "half influence is %f" % crowd.get_character_influence(fader))
			var error = blend_error(fader, 0.5)
			expect(error < TOLERANCE, "at influence 0.5 the poses are %f rad from halfway" % error)
			fader.influence = 0.0
		42:
			var error = rest_error(fader)
			expect(error < TOLERANCE, "at influence 0 the poses are %f rad from the animation" % error)
			fader.influence = 1.0
		43:
			var error = blend_error(fader, 1.0)
			expect(error < TOLERANCE, "back at influence 1 the poses are %f rad from the gaze" % error)
			# Crowd-wide: it multiplies the character's.
			crowd.influence = 0.5
		44:
			expect(crowd.get_character_influence(fader) == 0.5, "the crowd's half gives %f" % crowd.get_character_influence(fader))
			var error = blend_error(fader, 0.5)
			expect(error < TOLERANCE, "at the crowd's 0.5 the poses are %f rad from halfway" % error)
			crowd.active = false
		45:
			var error = rest_error(fader)
			expect(error < TOLERANCE, "with the crowd inactive the poses are %f rad from the animation" % error)
			expect(crowd.get_character_influence(lidded) == 0.0, "an inactive crowd's character has influence")
			crowd.active = true
			crowd.influence = 1.0
		46:
			expect(blend_error(fader, 1.0) < TOLERANCE, "the crowd back on")
			# A fade: 1 s to inactive.
			fader.influence_fade_time = 1.0
			fader.active = false
		61:
			var influence = crowd.get_character_influence(fader)
			expect(abs(influence - 0.5) < 0.02, "half way through the fade the influence is %f" % influence)
			expect(blend_error(fader, influence) < TOLERANCE, "the poses follow the fade")
		77:
			expect(crowd.get_character_influence(fader) == 0.0, "after the fade the influence is %f" % crowd.get_character_influence(fader))
			expect(rest_error(fader) < TOLERANCE, "after the fade the poses are not the animation's")
			# The animation sets a pose: an inactive character leaves it alone.
			var skeleton = fader.get_parent()
			held_pose = Transform(Basis(Vector3(0, 1, 0), 0.3), Vector3.ZERO)
			skeleton.set_bone_pose(crowd.get_chain_bones(fader)[2], held_pose)
		80:
			var skeleton = fader.get_parent()
			var pose = skeleton.get_bone_pose(crowd.get_chain_bones(fader)[2])
			expect(pose.is_equal_approx(held_pose), "an inactive character's bone was written")
			skeleton.set_bone_pose(crowd.get_chain_bones(fader)[2], Transform())
			# Back on, fading in over 1 s: attention kept running.
			fader.active = true
		81:
			var influence = crowd.get_character_influence(fader)
			expect(influence > 0.0 and influence < 0.1, "fading in, the influence is %f" % influence)
		112:
			expect(crowd.get_character_influence(fader) == 1.0, "after fading in the influence is %f" % crowd.get_character_influence(fader))
			expect(blend_error(fader, 1.0) < TOLERANCE, "after fading in the poses are not the gaze")
			# Limits, live: the eyes turn no more than 4 degrees; the skeleton is mapped again.
			fader.max_eye_angle = 4.0
			fader.max_head_turn = 20.0
			expect(crowd.set_gaze_target(fader, Vector3(2.5, 1.9, 1.5)), "the point again after the new limits")
			# Attention settings, live.
			lidded.attention_fraction = 0.9
			lidded.attention_model = 1
		150:
			var skeleton = fader.get_parent()
			var bones = crowd.get_chain_bones(fader)
			for k in [bones.size() - 2, bones.size() - 1]:
				var turned = rad2deg(angle(skeleton.get_bone_pose(bones[k]).basis.get_rotation_quat(), Quat()))
				expect(turned <= 4.0 + 0.01, "an eye turned %f degrees beyond max_eye_angle = 4" % turned)
			expect(blend_error(fader, 1.0) < TOLERANCE, "the poses with the new limits are not the gaze")
			lidded.attention_model = 0
			lidded.attention_fraction = -1.0
		END:
			expect(crowd.remove_conversation(conversation), "the conversation was not removed")
			expect(crowd.get_conversation(speaker) == -1, "the speaker is still in a conversation")
			expect_error("/root/Controls/CrowdGaze: CrowdGaze.remove_conversation: not found: no conversation")
			expect(not crowd.remove_conversation(conversation), "a conversation removed twice")
			expect(blink_frames > 0 and shape_frames > 0, "no blink in %d frames" % END)
			var share = float(listener_on_speaker) / max(listener_frames, 1)
			print("CROWDGAZE CONTROLS listener_on_speaker=%.3f blink_frames=%d started=%d stopped=%d" % [share, blink_frames, started, stopped])
			expect(share > 0.5, "the listener looked at the speaker %.0f%% of the time" % (100.0 * share))
			expect(started > 0 and stopped > 0, "looking signals: %d started, %d stopped" % [started, stopped])
			for failure in failures:
				print("CROWDGAZE CONTROLS FAILURE " + failure)
			for node in [fader, lidded, speaker, listener]:
				node.get_parent().get_parent().free()
			if failures.empty():
				print("CROWDGAZE CONTROLS PASSED")
				get_tree().quit(0)
			else:
				print("CROWDGAZE CONTROLS FAILED")
				get_tree().quit(1)
