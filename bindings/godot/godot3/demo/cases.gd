# What a Godot user may do to the addon, headless (scripts/godot-check runs
# res://cases.tscn as it runs bad_input.tscn): two crowds with crowd paths, two characters
# on one skeleton, mirrored scales, a head re-parented, live property changes, a removed
# script, a character instanced on a Thread, negative and NaN deltas, a 3000-bone skeleton
# without a head, bad crowd settings. Each case either works (checked here, from Godot's
# side) or prints one error that names the node: "EXPECT ERROR <text>" first, and
# scripts/godot-check checks that exactly those errors appear, once each.
extends Spatial

const Builder = preload("res://lib/bvh_skeleton.gd")
const CharacterScript = preload("res://addons/crowdgaze/CrowdGazeCharacter.gdns")
const TargetScript = preload("res://addons/crowdgaze/GazeTarget.gdns")
const CrowdScript = preload("res://addons/crowdgaze/CrowdGaze.gdns")

var builder
var frame = 0
var failures = []
var thread
var frozen = []
var removed_bones = []
var reparented_neck = -1
var post

onready var crowd_a = $CrowdA
onready var crowd_b = $CrowdB


func expect(condition, what):
	if not condition:
		failures.append("frame %d: %s" % [frame, what])


func expect_error(text):
	print("EXPECT ERROR " + text)


func make_person(name, crowd_path):
	var root = Spatial.new()
	root.name = name
	var skeleton = Skeleton.new()
	skeleton.name = "Skeleton"
	builder.build(skeleton)
	root.add_child(skeleton)
	var gaze = CharacterScript.new()
	gaze.name = "Gaze"
	gaze.crowd = NodePath(crowd_path)
	skeleton.add_child(gaze)
	return root


func gaze_of(name):
	return get_node(name + "/Skeleton/Gaze")


func chain_poses(gaze, crowd):
	var skeleton = gaze.get_parent()
	var poses = []
	for bone in crowd.get_chain_bones(gaze):
		poses.append(skeleton.get_bone_pose(bone))
	return poses


func _ready():
	builder = Builder.new()
	var error = builder.load_shared("bvh/zombie.bvh", 1.7)
	if error != "":
		failures.append(error)


func _make_on_thread(_unused):
	# A loader thread instancing a character (added to the tree on the main thread).
	return make_person("Threaded", "/root/Cases/CrowdA")


func _process(_delta):
	frame += 1
	match frame:
		2:
			# Two crowds: each character joins the one its crowd path names, else its
			# nearest CrowdGaze ancestor.
			add_child(make_person("A0", "/root/Cases/CrowdA"))
			add_child(make_person("B0", "/root/Cases/CrowdB"))
			var b1 = make_person("B1", "")
			b1.translation = Vector3(2, 0, 0)
			crowd_b.add_child(b1)
			expect(crowd_a.get_character_count() == 1, "CrowdA holds %d, not 1" % crowd_a.get_character_count())
			expect(crowd_b.get_character_count() == 2, "CrowdB holds %d, not 2" % crowd_b.get_character_count())
			expect(gaze_of("A0").get_crowd_node() == crowd_a, "A0's crowd")
			expect(crowd_b.get_node("B1/Skeleton/Gaze").get_crowd_node() == crowd_b, "B1's crowd")
			expect(crowd_b.get_chain_bones(gaze_of("A0")).size() == 0, "A0 is in CrowdB too")
			# No path, no ancestor, two crowds: which one is ambiguous.
			expect_error("/root/Cases/Lost/Skeleton/Gaze: CrowdGazeCharacter._ready: 2 CrowdGaze nodes are in the tree and none is an ancestor of this node: set its crowd path")
			add_child(make_person("Lost", ""))
			# A path to a node that is not a crowd.
			post = TargetScript.new()
			post.name = "Post"
			post.look_at_height = 1.0
			crowd_a.add_child(post)
			expect(crowd_a.get_target_count() == 1, "the post did not join CrowdA")
			expect(crowd_b.get_target_count() == 0, "the post joined CrowdB")
			expect_error("/root/Cases/Astray/Skeleton/Gaze: CrowdGazeCharacter._ready: crowd = '/root/Cases/CrowdA/Post' names a Spatial")
			add_child(make_person("Astray", "/root/Cases/CrowdA/Post"))
			# Two characters on one skeleton: the second is refused, naming both.
			var second = CharacterScript.new()
			second.name = "Gaze2"
			second.crowd = NodePath("/root/Cases/CrowdB")
			expect_error("/root/Cases/B0/Skeleton/Gaze2: CrowdGazeCharacter._enter_tree: its skeleton is driven already by the CrowdGazeCharacter /root/Cases/B0/Skeleton/Gaze")
			get_node("B0/Skeleton").add_child(second)
			expect(crowd_b.get_character_count() == 2, "the second character on B0's skeleton joined")
			# Mirrored at registration: refused.
			var mirror = make_person("Mirror", "/root/Cases/CrowdA")
			mirror.scale = Vector3(-1, 1, 1)
			expect_error("/root/Cases/Mirror/Skeleton/Gaze: CrowdGazeCharacter._enter_tree: invalid argument: the skeleton's global transform is mirrored")
			add_child(mirror)
			# 3000 bones and no head: one error of reasonable length (godot-check checks
			# every error line is under 2000 characters).
			var big = Spatial.new()
			big.name = "Big"
			var skeleton = Skeleton.new()
			skeleton.name = "Skeleton"
			for b in range(3000):
				skeleton.add_bone("a_long_bone_name_from_some_exporter_%04d_%s" % [b, "x".repeat(120)])
				if b > 0:
					skeleton.set_bone_parent(b, b - 1)
			big.add_child(skeleton)
			var big_gaze = CharacterScript.new()
			big_gaze.name = "Gaze"
			big_gaze.crowd = NodePath("/root/Cases/CrowdA")
			skeleton.add_child(big_gaze)
			expect_error("/root/Cases/Big/Skeleton/Gaze: CrowdGazeCharacter._enter_tree: invalid argument: no head bone: none of the 3000 bones")
			add_child(big)
			# Bad crowd settings, reported as given.
			var bad = CrowdScript.new()
			bad.name = "BadCrowd"
			bad.max_characters = -5
			bad.camera_is_viewer = false
			expect_error("/root/Cases/BadCrowd: CrowdGaze._enter_tree: invalid argument: max_characters = -5")
			add_child(bad)
			bad.free()
		3:
			thread = Thread.new()
			thread.start(self, "_make_on_thread")
		5:
			var person = thread.wait_to_finish()
			person.translation = Vector3(0, 0, 3)
			add_child(person)
			expect(crowd_a.get_character_count() == 2, "the character made on a thread did not join (CrowdA holds %d)" % crowd_a.get_character_count())
		6:
			# Mirrored after registration: one error (however long it lasts), bones left alone.
			frozen = chain_poses(gaze_of("A0"), crowd_a)
			expect_error("/root/Cases/A0/Skeleton/Gaze: CrowdGaze._process: invalid argument: the skeleton's global transform is mirrored")
			get_node("A0").scale = Vector3(1, 1, -1)
			# A head re-parented: the chain is mapped again.
			var gaze = crowd_b.get_node("B1/Skeleton/Gaze")
			var skeleton = gaze.get_parent()
			var chain = crowd_b.get_chain_bones(gaze)
			var head = chain[chain.size() - 3]
			reparented_neck = chain[chain.size() - 4]
			skeleton.set_bone_parent(head, skeleton.get_bone_parent(reparented_neck))
		7, 8, 9, 10, 11:
			expect(chain_poses(gaze_of("A0"), crowd_a) == frozen, "a mirrored character's bones moved")
			if frame == 8:
				# Live property changes.
				var gaze = gaze_of("B0")
				var before = crowd_b.get_chain_bones(gaze).size()
				gaze.bone_map = "LeftEye=none,RightEye=none"
				expect(crowd_b.get_chain_bones(gaze).size() == before - 2, "bone_map did not take effect")
				expect_error("/root/Cases/B0/Skeleton/Gaze: CrowdGazeCharacter.set: invalid argument: impact = -1")
				gaze.impact = -1.0
				gaze.impact = 2.0
				post.look_at_height = 2.5
				crowd_a.set_gaze_target(gaze_of("Threaded"), post)
			if frame == 10:
				var point = crowd_a.get_gaze_point(gaze_of("Threaded"))
				var want = post.global_transform.origin + Vector3(0, 2.5, 0)
				expect(point.distance_to(want) < 1e-3, "look_at_height did not take effect: %s, not %s" % [point, want])
				# The character script removed: it leaves, its skeleton is left alone.
				var gaze = gaze_of("Threaded")
				removed_bones = crowd_a.get_chain_bones(gaze)
				gaze.set_script(null)
		12:
			get_node("A0").scale = Vector3(1, 1, 1)
			expect(crowd_a.get_character_count() == 1, "a node without its script is still in the crowd (CrowdA holds %d)" % crowd_a.get_character_count())
			var skeleton = get_node("Threaded/Skeleton")
			for bone in removed_bones:
				skeleton.set_bone_pose(bone, Transform())
			var gaze = crowd_b.get_node("B1/Skeleton/Gaze")
			expect(not (reparented_neck in crowd_b.get_chain_bones(gaze)), "the re-parented head kept its old chain")
			# Godot 3's negative deltas are no time passing: no error. A NaN delta: one
			# error, however often.
			crowd_a._process(-0.02)
			expect_error("/root/Cases/CrowdA: CrowdGaze._process: non-finite value: the frame's delta is NaN")
			crowd_a._process(NAN)
			crowd_a._process(NAN)
			# A third crowd entering later takes no one.
			var late = CrowdScript.new()
			late.name = "LateCrowd"
			late.camera_is_viewer = false
			add_child(late)
			expect(late.get_character_count() == 0, "the late crowd took %d characters" % late.get_character_count())
			expect(crowd_a.get_character_count() == 1 and crowd_b.get_character_count() == 2, "the late crowd changed the others")
			late.free()
		16:
			var skeleton = get_node("Threaded/Skeleton")
			for bone in removed_bones:
				expect(skeleton.get_bone_pose(bone) == Transform(), "the removed character's skeleton was written")
			for crowd in [crowd_a, crowd_b]:
				for person in ["A0", "B0"]:
					if crowd.get_chain_bones(gaze_of(person)).size() > 0:
						for q in crowd.get_joint_rotations(gaze_of(person)):
							expect(not is_nan(q.x), "a NaN rotation")
			for failure in failures:
				print("CROWDGAZE CASES FAILURE " + failure)
			if failures.empty():
				print("CROWDGAZE CASES PASSED")
				get_tree().quit(0)
			else:
				print("CROWDGAZE CASES FAILED")
				get_tree().quit(1)
