# Bad input for the addon, headless (scripts/godot-check runs res://bad_input.tscn): an empty
# crowd, a skeleton without a head, a character that is not under a skeleton, a bad bone
# map, a full crowd, characters freed and removed mid-run, NaN and infinite transforms, and
# bad arguments to every query; then every exported method of the three nodes called with
# too few and too many arguments, wrong types, null, a freed object, NaN, infinite and huge
# values, and every property set to them (hostile_calls, hostile_properties). Each case that must report prints "EXPECT ERROR <text>"
# first: scripts/godot-check checks that exactly those errors appear, once each, and no
# others. Prints "CROWDGAZE BAD INPUT PASSED" (or FAILED) and quits with 0 (or 1).
extends Spatial

const Builder = preload("res://lib/bvh_skeleton.gd")
const CharacterScript = preload("res://addons/crowdgaze/CrowdGazeCharacter.gdns")
const TargetScript = preload("res://addons/crowdgaze/GazeTarget.gdns")
const CrowdScript = preload("res://addons/crowdgaze/CrowdGaze.gdns")

var builder
var frame = 0
var failures = []
var people = []
var target
var frozen = []

onready var crowd = $CrowdGaze


func expect(condition, what):
	if not condition:
		failures.append("frame %d: %s" % [frame, what])


func expect_error(text):
	print("EXPECT ERROR " + text)


func person(name, position):
	var root = Spatial.new()
	root.name = name
	var skeleton = Skeleton.new()
	skeleton.name = "Skeleton"
	builder.build(skeleton)
	root.add_child(skeleton)
	var gaze = CharacterScript.new()
	gaze.name = "Gaze"
	skeleton.add_child(gaze)
	root.translation = position
	add_child(root)
	return root


func _ready():
	builder = Builder.new()
	var error = builder.load_shared("bvh/zombie.bvh", 1.7)
	if error != "":
		failures.append(error)


func chain_poses(root):
	var skeleton = root.get_node("Skeleton")
	var poses = []
	for bone in crowd.get_chain_bones(root.get_node("Skeleton/Gaze")):
		poses.append(skeleton.get_bone_pose(bone))
	return poses


func _process(_delta):
	frame += 1
	match frame:
		3:
			# An empty crowd has stepped: nothing to do, nothing reported.
			expect(crowd.get_character_count() == 0, "the empty crowd holds characters")
			# A skeleton without a head: one error naming the node and its bones.
			var root = Spatial.new()
			root.name = "Headless"
			var skeleton = Skeleton.new()
			skeleton.name = "Skeleton"
			for bone in ["Hips", "Spine", "Tail"]:
				skeleton.add_bone(bone)
			skeleton.set_bone_parent(1, 0)
			skeleton.set_bone_parent(2, 1)
			var gaze = CharacterScript.new()
			gaze.name = "Gaze"
			skeleton.add_child(gaze)
			root.add_child(skeleton)
			expect_error("/root/BadInput/Headless/Skeleton/Gaze: CrowdGazeCharacter._enter_tree: invalid argument: no head bone: none of the 3 bones ('Hips', 'Spine', 'Tail')")
			add_child(root)
			expect(crowd.get_character_count() == 0, "the headless skeleton joined")
			# A character that is not under a skeleton.
			var stray = CharacterScript.new()
			stray.name = "Stray"
			expect_error("/root/BadInput/Stray: CrowdGazeCharacter._enter_tree: a CrowdGazeCharacter must be a child of a Skeleton")
			add_child(stray)
			# A bone map that does not parse.
			var odd = Spatial.new()
			odd.name = "OddMap"
			var odd_skeleton = Skeleton.new()
			odd_skeleton.name = "Skeleton"
			builder.build(odd_skeleton)
			var odd_gaze = CharacterScript.new()
			odd_gaze.name = "Gaze"
			odd_gaze.bone_map = "Head=brain"
			odd_skeleton.add_child(odd_gaze)
			odd.add_child(odd_skeleton)
			expect_error("/root/BadInput/OddMap/Skeleton/Gaze: CrowdGazeCharacter._enter_tree: invalid argument: bone map: 'brain' is not a role")
			add_child(odd)
		5:
			for k in range(3):
				people.append(person("Person%d" % k, Vector3(1.5 * k, 0, 0)))
			expect(crowd.get_character_count() == 3, "3 characters joined, the crowd holds %d" % crowd.get_character_count())
			# The crowd holds 3 (max_characters): a fourth is refused, once.
			expect_error("/root/BadInput/Extra/Skeleton/Gaze: CrowdGazeCharacter._enter_tree: capacity exceeded")
			person("Extra", Vector3(0, 0, 3))
			target = TargetScript.new()
			target.name = "Lamp"
			target.translation = Vector3(0, 0, 2)
			add_child(target)
			expect(crowd.get_target_count() == 1, "the target did not join")
		10:
			# Freed: out of the crowd at once.
			people[0].free()
			expect(crowd.get_character_count() == 2, "a freed character is still in the crowd")
			# Removed from the tree: out at once; back in: in again.
			remove_child(people[1])
			expect(crowd.get_character_count() == 1, "a removed character is still in the crowd")
		12:
			add_child(people[1])
			expect(crowd.get_character_count() == 2, "a character back in the tree did not rejoin")
			# The extra character may join now that there is room: free it instead.
			get_node("Extra").free()
		15:
			# NaN position: one error, the character keeps its last state.
			frozen = chain_poses(people[2])
			expect_error("/root/BadInput/Person2/Skeleton/Gaze: CrowdGaze._process: non-finite value: the skeleton's global transform is not finite; the character keeps its last state")
			people[2].translation = Vector3(NAN, 0, 0)
			# An infinite target: one error, it stays where it was.
			expect_error("/root/BadInput/Lamp: CrowdGaze._process: non-finite value: the target's global transform is not finite; the target stays where it was")
			target.translation = Vector3(0, INF, 2)
		16, 17, 18, 19:
			expect(chain_poses(people[2]) == frozen, "a stalled character's bones moved")
		20:
			people[2].translation = Vector3(3, 0, 0)
			target.translation = Vector3(0, 0, 2)
		22:
			# A NaN bone pose: reported once, and the pose is not overwritten by the addon.
			var skeleton = people[1].get_node("Skeleton")
			var spine = skeleton.find_bone("Spine1")
			expect_error("/root/BadInput/Person1/Skeleton/Gaze: CrowdGaze._process: non-finite value: bone Spine1's pose is not finite")
			skeleton.set_bone_pose(spine, Transform(Basis(Vector3(NAN, 0, 0), Vector3.UP, Vector3.BACK), Vector3.ZERO))
		24:
			var skeleton = people[1].get_node("Skeleton")
			skeleton.set_bone_pose(skeleton.find_bone("Spine1"), Transform())
		26:
			# Bad arguments to the queries: empty answers, no crash.
			expect(crowd.get_joint_rotations(null).size() == 0, "rotations of null")
			expect(crowd.get_chain_bones(self).size() == 0, "chain bones of a non-character")
			expect(crowd.get_gaze_target(target) == null, "the gaze target of a target")
			expect(crowd.get_gaze_point(42) == Vector3.ZERO, "the gaze point of a number")
			expect(not crowd.is_holding(null), "null is holding")
			expect(not crowd.is_attending("x"), "a string attends")
			expect(crowd.get_look_at_height(null) == 0.0, "the look-at height of null")
			expect(not crowd.clear_gaze_target(null), "clearing null's target")
			var gaze = people[1].get_node("Skeleton/Gaze")
			expect_error("set_gaze_target: the target is neither a point nor in the crowd")
			expect(not crowd.set_gaze_target(gaze, self), "looking at a node outside the crowd")
			expect_error("set_gaze_target: invalid argument: a character cannot look at itself")
			expect(not crowd.set_gaze_target(gaze, gaze), "looking at itself")
			expect(crowd.set_gaze_target(gaze, Vector3(1, 1.5, 3)), "looking at a point")
			expect(crowd.set_gaze_target(gaze, target), "looking at the target")
			expect(crowd.clear_gaze_target(gaze), "clearing the target")
		27:
			# The controls and outputs given bad values: empty answers or one error each.
			var gaze = people[1].get_node("Skeleton/Gaze")
			var other = people[2].get_node("Skeleton/Gaze")
			var freed = Spatial.new()
			freed.free()
			for bad in [null, "x", 42, freed, self, target, Vector3(NAN, 0, 0)]:
				expect(crowd.get_eyelids(bad) == Vector2.ZERO, "eyelids of %s" % str(bad))
				expect(crowd.get_character_influence(bad) == 0.0, "influence of %s" % str(bad))
				expect(crowd.get_conversation(bad) == -1, "conversation of %s" % str(bad))
			expect_error("/root/BadInput/CrowdGaze: CrowdGaze.set_conversation: members must be an Array of CrowdGazeCharacter nodes, not null")
			expect(crowd.set_conversation(null) == -1, "a conversation of null")
			# Once per cause: the same bad call again prints nothing.
			expect(crowd.set_conversation(null) == -1, "a conversation of null, again")
			expect_error("/root/BadInput/CrowdGaze: CrowdGaze.set_conversation: members must be an Array of CrowdGazeCharacter nodes, not a float")
			expect(crowd.set_conversation(INF) == -1, "a conversation of INF")
			expect_error("/root/BadInput/CrowdGaze: CrowdGaze.set_conversation: invalid argument: a conversation has 2 to 8 members, not 1; no conversation")
			expect(crowd.set_conversation([gaze]) == -1, "a conversation of one")
			expect_error("/root/BadInput/CrowdGaze: CrowdGaze.set_conversation: not found: member 1 is not a character of this crowd")
			expect(crowd.set_conversation([gaze, freed]) == -1, "a conversation with a freed node")
			expect_error("/root/BadInput/CrowdGaze: CrowdGaze.set_conversation: invalid argument: character")
			expect(crowd.set_conversation([gaze, gaze]) == -1, "a conversation with itself")
			var huge = []
			for k in range(100000):
				huge.append(gaze)
			# (The cause of one member, with another number: not reported again.)
			expect(crowd.set_conversation(huge) == -1, "a conversation of 100000")
			var id = crowd.set_conversation([gaze, other])
			expect(id >= 0 and crowd.get_conversation(other) == id, "a good conversation")
			expect_error("/root/BadInput/CrowdGaze: CrowdGaze.remove_conversation: id must be an int (from set_conversation), not a String")
			expect(not crowd.remove_conversation("x"), "removing conversation 'x'")
			expect_error("/root/BadInput/CrowdGaze: CrowdGaze.remove_conversation: not found: there is no conversation -5")
			expect(not crowd.remove_conversation(-5), "removing conversation -5")
			expect(not crowd.remove_conversation(-5), "removing conversation -5 again")
			expect_error("/root/BadInput/CrowdGaze: CrowdGaze.remove_conversation: not found: there is no conversation 9223372036854775807")
			expect(not crowd.remove_conversation(9223372036854775807), "removing a huge conversation")
			expect(crowd.remove_conversation(id), "removing the good conversation")
			# Out-of-range properties: one error each, naming the node and the value; the
			# character keeps its settings.
			var cases = [
				["influence", NAN, "influence = NaN"],
				["influence", 5.0, "influence = 5.0: it must be from 0 to 1"],
				["influence_fade_time", -1.0, "influence_fade_time = -1.0"],
				["influence_fade_time", INF, "influence_fade_time = inf"],
				["attention_fraction", 2.0, "attention_fraction = 2.0"],
				["attention_model", 9, "attention_model = 9"],
				["max_head_turn", INF, "max_head_turn = inf"],
				["max_eye_angle", -3.0, "max_eye_angle = -3.0"],
			]
			for case in cases:
				var good = gaze.get(case[0])
				expect_error("/root/BadInput/Person1/Skeleton/Gaze: CrowdGazeCharacter.set: invalid argument: " + case[2])
				gaze.set(case[0], case[1])
				gaze.set(case[0], good)
			expect(crowd.get_character_influence(gaze) == 1.0, "the influence after bad values")
			expect_error("/root/BadInput/Person1/Skeleton/Gaze: CrowdGazeCharacter.set_eyelid_mesh: eyelid_mesh = 'Nowhere' names no node")
			gaze.eyelid_mesh = NodePath("Nowhere")
			expect_error("/root/BadInput/Person1/Skeleton/Gaze: CrowdGazeCharacter.set_eyelid_mesh: eyelid_mesh = '..' names a Skeleton, not a MeshInstance")
			gaze.eyelid_mesh = NodePath("..")
			var face = MeshInstance.new()
			face.name = "Face"
			face.mesh = CubeMesh.new()
			gaze.add_child(face)
			expect_error("/root/BadInput/Person1/Skeleton/Gaze: CrowdGazeCharacter.set_eyelid_mesh: eyelid_mesh = 'Face' has no blink blend shape")
			gaze.eyelid_mesh = NodePath("Face")
			expect_error("/root/BadInput/Person1/Skeleton/Gaze: CrowdGazeCharacter.set_eyelid_mesh: eyelid_shapes names 'wink', which the mesh does not have (its blend shapes: none)")
			gaze.eyelid_shapes = "wink"
			face.free()
			gaze.eyelid_mesh = NodePath("")
			gaze.eyelid_shapes = ""
			# The crowd's controls.
			expect_error("/root/BadInput/CrowdGaze: CrowdGaze.set_active/set_influence/set_influence_fade_time: invalid argument: influence = NaN")
			crowd.influence = NAN
			crowd.influence = 1.0
			expect_error("/root/BadInput/CrowdGaze: CrowdGaze.set_active/set_influence/set_influence_fade_time: invalid argument: influence_fade_time = 1e300")
			crowd.influence_fade_time = 1e300
			crowd.influence_fade_time = 0.0
			gaze.talking = true
			gaze.talking = false
			# Wrong types: one error each, naming the node and the property, which keeps its
			# value; what GDScript converts on assignment (an int for a float, a String for a
			# NodePath) is taken.
			var person1 = "/root/BadInput/Person1/Skeleton/Gaze: CrowdGazeCharacter."
			expect_error(person1 + "influence: a String is not a float from 0 to 1; the value is kept")
			gaze.set("influence", "abc")
			expect_error(person1 + "active: a Vector3 is not a bool; the value is kept")
			gaze.set("active", Vector3.ONE)
			expect_error(person1 + "eyelid_mesh: an int is not a NodePath; the value is kept")
			gaze.set("eyelid_mesh", 42)
			expect_error(person1 + "attention_model: null is not an int (0 to 3); the value is kept")
			gaze.set("attention_model", null)
			expect_error(person1 + "max_head_turn: an Object is not a float (degrees); the value is kept")
			gaze.set("max_head_turn", freed)
			expect_error("/root/BadInput/CrowdGaze: CrowdGaze.influence: an Array is not a float from 0 to 1; the value is kept")
			crowd.set("influence", [1])
			expect_error("/root/BadInput/CrowdGaze: CrowdGaze.active: a String is not a bool; the value is kept")
			crowd.set("active", "yes")
			expect(gaze.influence == 1.0 and gaze.active and gaze.attention_model == 0, "a refused value was kept")
			expect(crowd.influence == 1.0 and crowd.active, "a refused crowd value was kept")
			gaze.influence = 0
			expect(gaze.influence == 0.0, "an int influence was refused")
			gaze.influence = 1
			gaze.eyelid_mesh = ""
			expect(gaze.eyelid_mesh == NodePath(""), "a String path was refused")
		28:
			hostile_calls()
			hostile_properties()
		30:
			expect(crowd.get_character_count() == 2, "the crowd holds %d characters at the end" % crowd.get_character_count())
			for root in [people[1], people[2]]:
				var rotations = crowd.get_joint_rotations(root.get_node("Skeleton/Gaze"))
				expect(rotations.size() == 8, "rotations after recovering")
				for q in rotations:
					expect(is_finite_quat(q), "a rotation is not finite")
			for failure in failures:
				print("CROWDGAZE BAD INPUT FAILURE " + failure)
			if failures.empty():
				print("CROWDGAZE BAD INPUT PASSED")
				get_tree().quit(0)
			else:
				print("CROWDGAZE BAD INPUT FAILED")
				get_tree().quit(1)


static func is_finite_quat(q):
	for v in [q.x, q.y, q.z, q.w]:
		if is_nan(v) or is_inf(v):
			return false
	return true


# Every exported method of the three nodes, with their argument counts (the callbacks
# Godot calls too: a script may call them).
const CROWD_METHODS = [
	["_enter_tree", 0], ["_ready", 0], ["_exit_tree", 0], ["_process", 1],
	["_get_configuration_warning", 0], ["get_character_count", 0], ["get_target_count", 0],
	["get_gaze_target", 1], ["get_gaze_point", 1], ["is_attending", 1], ["is_holding", 1],
	["get_chain_bones", 1], ["get_joint_rotations", 1], ["get_look_at_height", 1],
	["set_gaze_target", 2], ["clear_gaze_target", 1], ["get_frame_usec", 0],
	["get_frame_parts_usec", 0], ["get_eyelids", 1], ["get_character_influence", 1],
	["set_conversation", 1], ["remove_conversation", 1], ["get_conversation", 1],
	["get_following", 1],
]
const CHARACTER_METHODS = [
	["_enter_tree", 0], ["_ready", 0], ["_exit_tree", 0], ["_notification", 1],
	["_get_configuration_warning", 0], ["get_crowd_node", 0], ["_crowdgaze_join", 0],
]
const TARGET_METHODS = [["_enter_tree", 0], ["_ready", 0], ["_exit_tree", 0], ["_get_configuration_warning", 0]]


func nulls(count):
	var args = []
	for _k in range(count):
		args.append(null)
	return args


# Each method with one argument too many (and one too few when it takes any): one error
# each naming the node, method and arguments expected, nothing done; the same wrong call
# again is not reported again.
func wrong_counts(node, node_path, kind, methods):
	for entry in methods:
		var method = entry[0]
		var count = entry[1]
		expect_error("%s: %s.%s: too many arguments: it takes " % [node_path, kind, method])
		node.callv(method, nulls(count + 1))
		node.callv(method, nulls(count + 2))
		if count > 0:
			expect_error("%s: %s.%s: too few arguments: it takes " % [node_path, kind, method])
			node.callv(method, nulls(count - 1))


func hostile_calls():
	var gaze = people[1].get_node("Skeleton/Gaze")
	wrong_counts(crowd, "/root/BadInput/CrowdGaze", "CrowdGaze", CROWD_METHODS)
	wrong_counts(gaze, "/root/BadInput/Person1/Skeleton/Gaze", "CrowdGazeCharacter", CHARACTER_METHODS)
	wrong_counts(target, "/root/BadInput/Lamp", "GazeTarget", TARGET_METHODS)
	# Every value a script may pass where a character or target is expected: empty answers,
	# no crash; set_gaze_target says why once per cause.
	var freed = Spatial.new()
	freed.free()
	var values = [null, 0, -1, 1 << 62, NAN, INF, "x", "x".repeat(100000), freed, self, crowd,
		target, Vector3(NAN, 0, 0), Vector3(INF, 0, 0), Vector3(1e30, 1e30, 1e30), [], {},
		Transform(), PoolByteArray()]
	expect_error("CrowdGaze.set_gaze_target: the character is not in the crowd")
	# ("the target is neither a point nor in the crowd" was reported at frame 26: not again.)
	expect_error("CrowdGaze.set_gaze_target: non-finite value: target point contains NaN")
	expect_error("CrowdGaze.set_gaze_target: non-finite value: target point contains inf")
	for value in values:
		expect(crowd.get_gaze_target(value) == null, "the gaze target of %s" % [value])
		expect(crowd.get_gaze_point(value) == Vector3.ZERO, "the gaze point of %s" % [value])
		expect(not crowd.is_attending(value), "%s attends" % [value])
		expect(not crowd.is_holding(value), "%s holds" % [value])
		expect(crowd.get_chain_bones(value).size() == 0, "the chain bones of %s" % [value])
		expect(crowd.get_joint_rotations(value).size() == 0, "the rotations of %s" % [value])
		expect(crowd.get_look_at_height(value) == 0.0, "the look-at height of %s" % [value])
		expect(crowd.get_following(value) == null, "the followed point of %s" % [value])
		expect(not crowd.clear_gaze_target(value), "clearing the target of %s" % [value])
		expect(not crowd.set_gaze_target(value, target), "%s looking at the target" % [value])
		if not (typeof(value) == TYPE_OBJECT and is_instance_valid(value) and value == target):
			var point = typeof(value) == TYPE_VECTOR3 and is_finite_vector(value)
			expect(crowd.set_gaze_target(gaze, value) == point, "%s as a gaze target" % [value])
	expect(crowd.clear_gaze_target(gaze), "clearing the character's target")
	# Frame deltas of every kind: a number steps (a huge one is clamped by the library or
	# refused), anything else is reported once and skips the frame.
	expect_error("/root/BadInput/CrowdGaze: CrowdGaze._process: the delta must be a number of seconds")
	for delta in ["x", null, Vector3.ZERO]:
		crowd._process(delta)
	crowd._process(0)
	crowd._process(-1e30)
	crowd._process(1e30)
	expect(crowd.get_character_count() == 2, "hostile calls changed the crowd")
	for value in [null, "x", NAN, 1 << 62]:
		gaze._notification(value)
	expect(gaze.get_crowd_node() == crowd, "the character's crowd after hostile calls")


static func is_finite_vector(v):
	return not (is_nan(v.x) or is_nan(v.y) or is_nan(v.z) or is_inf(v.x) or is_inf(v.y) or is_inf(v.z))


# Every property of the three nodes set to hostile values: the crowd's settings on new
# crowds entering the tree (each refused value reported once, naming the node and the value
# as given), the character's and the target's on nodes in the crowd (reported once, the old
# value kept).
# [property, value, the error it gives a crowd entering the tree ("" for none)]
const CROWD_SETTINGS = [
	["seed", 1 << 62, ""], ["seed", -1, ""],
	["max_characters", -5, "invalid argument: max_characters = -5: it must be a count"],
	["max_characters", 1 << 40, "invalid argument: max_characters = 1099511627776: it must be a count"],
	["max_targets", -1, "invalid argument: max_targets = -1: it must be a count"],
	["max_distance", NAN, "non-finite value: max_distance is NaN"],
	["max_distance", INF, "non-finite value: max_distance is inf"],
	["max_distance", 1e300, "invalid argument: max_distance = 1e300: too large"],
	["max_distance", -1.0, "invalid argument: max_distance is -1, must be in"],
	["field_of_view", NAN, "invalid argument: field_of_view = NaN: it must be from 0.6 to 360 degrees"],
	["field_of_view", 1e300, "invalid argument: field_of_view = 1e300: it must be from 0.6 to 360 degrees"],
	["attention_fraction_min", NAN, "non-finite value: attention_fraction_min is NaN"],
	["attention_fraction_max", INF, "non-finite value: attention_fraction_max is inf"],
	["attention_fraction_min", 2.0, "invalid argument: attention_fraction_min is 2, must be in [0, 1]"],
	["threads", -1, "invalid argument: threads = -1: it must be a count"],
	["threads", 1 << 40, "invalid argument: threads = 1099511627776: it must be a count"],
	["attention_period", 0, "invalid argument: attention_period is 0, must be 1..=64"],
	["attention_period", 65, "invalid argument: attention_period is 65, must be 1..=64"],
	["lod_distance", NAN, "non-finite value: lod_distance is NaN"],
	["lod_distance", -INF, "non-finite value: lod_distance is -inf"],
	["far_attention_period", 1 << 62, "invalid argument: far_attention_period = 4611686018427387904: it must be a count"],
	["viewer_impact", NAN, "CrowdGaze._process: the camera as the viewer: "],
	["viewer_impact", -1e300, "CrowdGaze._process: the camera as the viewer: "],
	["camera_is_viewer", false, ""],
	["gaze_following", true, ""],
	["following_strength", 2, "invalid argument: following_strength = 2: it must be 0 (Milgram) or 1 (Gallup)"],
	["following_strength", -1, "invalid argument: following_strength = -1: it must be 0 (Milgram) or 1 (Gallup)"],
]


# Every property of the three nodes set to hostile values: the crowd's settings on new
# crowds entering the tree, with a camera as the viewer (each refused value reported once,
# naming the node and the value as given), the character's and the target's on nodes in the
# crowd (reported once per cause, the old value kept). A value of the wrong type is refused
# by gdnative before the addon sees it: its message names no node (one case, below).
func hostile_properties():
	var camera = Camera.new()
	camera.name = "Camera"
	add_child(camera)
	camera.make_current()
	var k = 0
	for entry in CROWD_SETTINGS:
		var node = CrowdScript.new()
		node.name = "Settings%d" % k
		node.set(entry[0], entry[1])
		var expected = entry[2]
		if expected != "":
			if not expected.begins_with("CrowdGaze."):
				expected = "CrowdGaze._enter_tree: " + expected
			expect_error("/root/BadInput/Settings%d: %s" % [k, expected])
		add_child(node)
		for _frame in range(2):
			node._process(1.0 / 30.0)
		node.free()
		k += 1
	camera.free()
	# Values of the wrong type for every property: one error each naming the node and the
	# property, the value kept; an int for a float and a whole float for an int are taken.
	wrong_types(crowd, "/root/BadInput/CrowdGaze: CrowdGaze", CROWD_PROPERTIES)
	crowd.max_distance = 12
	expect(crowd.max_distance == 12.0, "an int max_distance was refused")
	crowd.max_distance = 10.0
	var gaze = people[2].get_node("Skeleton/Gaze")
	var path = "/root/BadInput/Person2/Skeleton/Gaze: CrowdGazeCharacter.set: invalid argument: "
	expect_error(path + "impact = NaN")
	expect_error(path + "impact = inf")
	expect_error(path + "impact = -1")
	expect_error(path + "impact = -inf")
	for value in [NAN, INF, -1.0, 1e300, -INF, -0.0]:
		gaze.impact = value
	gaze.impact = 1.0
	expect_error(path + "bone map: 'xxxxxxxx")
	expect_error(path + "bone map: '' is not a role")
	expect_error(path + "bone map: 'head=head' is not a role")
	expect_error(path + "bone map: 'Head' is not NAME=ROLE")
	expect_error(path + "bone map: bone 'Spine1' is given twice")
	for value in ["x".repeat(100000), "=", ",,,", "Head=head=head", "Head", "Spine1=neck,Spine1=spine"]:
		gaze.bone_map = value
	gaze.bone_map = ""
	expect(crowd.get_chain_bones(gaze).size() == 8, "the character's chain after hostile bone maps")
	gaze.crowd = NodePath("/root/Nowhere")
	gaze.crowd = NodePath()
	expect_error("/root/BadInput/Person2/Skeleton/Gaze: CrowdGazeCharacter.set_mapping_report: mapping_report is read-only")
	gaze.mapping_report = "x"
	gaze.mapping_report = "y"
	expect(gaze.mapping_report.begins_with("gaze chain of 8 joints"), "the mapping report: " + gaze.mapping_report)
	path = "/root/BadInput/Lamp: GazeTarget.set_look_at_height/set_impact: "
	expect_error(path + "non-finite value: look_at_height is NaN")
	expect_error(path + "non-finite value: look_at_height is inf")
	expect_error(path + "invalid argument: look_at_height is -1000000000000000000000000000000, must be in")
	for value in [NAN, INF, 1e300, -1e30]:
		target.look_at_height = value
	target.look_at_height = 0.0
	expect_error(path + "invalid argument: impact = NaN")
	expect_error(path + "invalid argument: impact = -1")
	expect_error(path + "invalid argument: impact = inf")
	for value in [NAN, -1.0, 1e300]:
		target.impact = value
	target.impact = 1.0
	target.crowd = NodePath("/root/Nowhere")
	target.crowd = NodePath()
	expect(crowd.get_target_count() == 1, "the target left after hostile properties")
	wrong_types(gaze, "/root/BadInput/Person2/Skeleton/Gaze: CrowdGazeCharacter", CHARACTER_PROPERTIES)
	wrong_types(target, "/root/BadInput/Lamp: GazeTarget", TARGET_PROPERTIES)
	gaze.impact = 2
	expect(gaze.impact == 2.0, "an int impact was refused")
	gaze.impact = 1.0
	expect(crowd.get_character_count() == 2 and crowd.get_chain_bones(gaze).size() == 8, "wrong types changed the character")


# Each property's Godot type, and values of other types for it.
const CROWD_PROPERTIES = [
	["seed", "int"], ["max_characters", "int"], ["max_targets", "int"], ["max_distance", "float"],
	["field_of_view", "float"], ["attention_fraction_min", "float"],
	["attention_fraction_max", "float"], ["threads", "int"], ["attention_period", "int"],
	["lod_distance", "float"], ["far_attention_period", "int"], ["camera_is_viewer", "bool"],
	["viewer_impact", "float"], ["gaze_following", "bool"],
]
const CHARACTER_PROPERTIES = [["crowd", "NodePath"], ["bone_map", "String"], ["impact", "float"]]
const TARGET_PROPERTIES = [["crowd", "NodePath"], ["look_at_height", "float"], ["impact", "float"]]


static func with_article(name):
	return ("an " if name[0] in ["a", "e", "i", "o", "u"] else "a ") + name


# Each property set to a String (a Vector3 for the String and NodePath ones: a String is
# taken as a NodePath, as GDScript converts it), then to null: one error each, the value
# unchanged.
func wrong_types(node, prefix, properties):
	for entry in properties:
		var before = node.get(entry[0])
		var textual = entry[1] in ["String", "NodePath"]
		var wrong = Vector3(1, 2, 3) if textual else "x"
		var wrong_name = "a Vector3" if textual else "a String"
		expect_error("%s.%s: %s is not %s; the value is kept" % [prefix, entry[0], wrong_name, with_article(entry[1])])
		node.set(entry[0], wrong)
		node.set(entry[0], wrong)
		expect_error("%s.%s: null is not %s; the value is kept" % [prefix, entry[0], with_article(entry[1])])
		node.set(entry[0], null)
		expect(typeof(node.get(entry[0])) == typeof(before) and str(node.get(entry[0])) == str(before), "%s.%s changed" % [prefix, entry[0]])
