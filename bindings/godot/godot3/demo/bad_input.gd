# Bad input for the addon, headless (scripts/godot-check runs res://bad_input.tscn): an empty
# crowd, a skeleton without a head, a character that is not under a skeleton, a bad bone
# map, a full crowd, characters freed and removed mid-run, NaN and infinite transforms, and
# bad arguments to every query. Each case that must report prints "EXPECT ERROR <text>"
# first: scripts/godot-check checks that exactly those errors appear, once each, and no
# others. Prints "CROWDGAZE BAD INPUT PASSED" (or FAILED) and quits with 0 (or 1).
extends Spatial

const Builder = preload("res://lib/bvh_skeleton.gd")
const CharacterScript = preload("res://addons/crowdgaze/CrowdGazeCharacter.gdns")
const TargetScript = preload("res://addons/crowdgaze/GazeTarget.gdns")

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
	var data = OS.get_environment("CROWDGAZE_DATA")
	if data == "":
		data = ProjectSettings.globalize_path("res://").plus_file("../../../../../shared/data")
	builder = Builder.new()
	var error = builder.load_bvh(data.plus_file("bvh/zombie.bvh"), 1.7)
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
			expect_error("/root/BadInput/CrowdGaze: CrowdGaze.set_conversation: invalid argument: a conversation has 2 to 8 members, not 100000")
			expect(crowd.set_conversation(huge) == -1, "a conversation of 100000")
			var id = crowd.set_conversation([gaze, other])
			expect(id >= 0 and crowd.get_conversation(other) == id, "a good conversation")
			expect_error("/root/BadInput/CrowdGaze: CrowdGaze.remove_conversation: id must be an int (from set_conversation), not a String")
			expect(not crowd.remove_conversation("x"), "removing conversation 'x'")
			expect_error("/root/BadInput/CrowdGaze: CrowdGaze.remove_conversation: not found: there is no conversation -5")
			expect(not crowd.remove_conversation(-5), "removing conversation -5")
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
			var person1 = "/root/BadInput/Person1/Skeleton/Gaze: CrowdGazeCharacter.set: "
			expect_error(person1 + "influence was given a String: it must be a float from 0 to 1")
			gaze.set("influence", "abc")
			expect_error(person1 + "active was given a Vector3: it must be a bool")
			gaze.set("active", Vector3.ONE)
			expect_error(person1 + "eyelid_mesh was given an int: it must be a NodePath")
			gaze.set("eyelid_mesh", 42)
			expect_error(person1 + "attention_model was given null: it must be an int")
			gaze.set("attention_model", null)
			expect_error(person1 + "max_head_turn was given an Object: it must be a float")
			gaze.set("max_head_turn", freed)
			expect_error("/root/BadInput/CrowdGaze: CrowdGaze.set: influence was given an Array: it must be a float")
			crowd.set("influence", [1])
			expect_error("/root/BadInput/CrowdGaze: CrowdGaze.set: active was given a String: it must be a bool")
			crowd.set("active", "yes")
			expect(gaze.influence == 1.0 and gaze.active and gaze.attention_model == 0, "a refused value was kept")
			expect(crowd.influence == 1.0 and crowd.active, "a refused crowd value was kept")
			gaze.influence = 0
			expect(gaze.influence == 0.0, "an int influence was refused")
			gaze.influence = 1
			gaze.eyelid_mesh = ""
			expect(gaze.eyelid_mesh == NodePath(""), "a String path was refused")
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
