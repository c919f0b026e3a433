# The demo's checks, read from Godot's side after the CrowdGaze node has run each frame
# (process_priority 200, after its 100): for every character,
#   1. each chain bone's local rotation, from the Skeleton's global bone poses (the first
#      relative to the character node's frame), equals the rotation the library returned
#      (get_joint_rotations) within 1e-5 rad;
#   2. once its gaze has settled on a target (is_holding; attention's or an explicit one),
#      each eye's forward (its rest forward, the skeleton's +Z, carried by the eye bone's
#      global pose) points at the target's look-at point within 2 degrees;
#   3. the crowd holds exactly the character nodes in the tree (freed people leave at once);
#   4. gaze following: the onlookers' eyes, once their gaze holds, point at the facade point
#      they stare at, within 2 degrees; at least one other character glances there
#      (get_following gives that point, and character_followed_gaze is emitted).
# 1 and 2 apply at full influence: the fading bystander's frames below it are counted (its
# gaze must fade out and back in) and left to controls.gd, which checks the blend.
# Prints the figures and "CROWDGAZE CHECK PASSED" (or FAILED), then quits with 0 (or 1).
extends Node

const POSE_TOLERANCE = 1e-5
const EYE_TOLERANCE_DEGREES = 2.0

var demo
var frames = 0
var worst_pose = 0.0
var worst_eye = 0.0
var worst_eye_where = ""
var eye_samples = 0
var attending = {}
var targets_seen = {}
var failures = []
var faded_frames = 0
var onlooker_frames = 0   # frames an onlooker's gaze held on the facade point
var followers = {}     # characters (not onlookers) seen following the onlookers' gaze
var eye_forward = {}   # skeleton instance id -> [left, right] eye forward in the eye's frame


func _ready():
	process_priority = 200


# The angle between two rotations, precise near 0.
static func angle(a, b):
	var q = a.inverse() * b
	return 2.0 * atan2(Vector3(q.x, q.y, q.z).length(), abs(q.w))


# A bone's rest pose in the skeleton's frame.
static func rest_global(skeleton, bone):
	var pose = skeleton.get_bone_rest(bone)
	var parent = skeleton.get_bone_parent(bone)
	while parent >= 0:
		pose = skeleton.get_bone_rest(parent) * pose
		parent = skeleton.get_bone_parent(parent)
	return pose


# The point the crowd's characters look at on a target node.
func look_at_point(target):
	var origin = target.global_transform.origin
	if target is Camera:
		return origin
	if target.has_method("get_crowd_node"):   # a CrowdGazeCharacter
		return origin + Vector3.UP * demo.crowd.get_look_at_height(target)
	return origin + Vector3.UP * target.look_at_height


func fail(message):
	if failures.size() < 20:
		failures.append("frame %d: %s" % [frames, message])


func _process(_delta):
	frames += 1
	var crowd = demo.crowd
	var characters = get_tree().get_nodes_in_group("_crowdgaze_characters")
	if crowd.get_character_count() != characters.size():
		fail("the crowd holds %d characters, the tree %d" % [crowd.get_character_count(), characters.size()])
	for gaze in characters:
		check_character(crowd, gaze)
	if demo.time >= demo.seconds - 1e-6:
		finish()


func check_character(crowd, gaze):
	# A character whose gaze fades (demo.gd's fading bystander) is blended with its walk,
	# which only the walk knows: its poses are the library's only at full influence
	# (controls.gd checks the blend itself).
	if crowd.get_character_influence(gaze) < 1.0:
		faded_frames += 1
		return
	var skeleton = gaze.get_parent()
	var bones = crowd.get_chain_bones(gaze)
	var rotations = crowd.get_joint_rotations(gaze)
	if bones.size() < 3 or rotations.size() != bones.size():
		fail("%s: %d chain bones, %d rotations" % [gaze.get_path(), bones.size(), rotations.size()])
		return
	var node = gaze.global_transform
	var z = node.basis.z
	var frame = Transform(Basis(Vector3.UP, atan2(z.x, z.z)), node.origin)
	var place = skeleton.global_transform
	for k in range(bones.size()):
		var pose = place * skeleton.get_bone_global_pose(bones[k])
		var parent = frame
		if k > 0:
			parent = place * skeleton.get_bone_global_pose(skeleton.get_bone_parent(bones[k]))
		var local = (parent.affine_inverse() * pose).basis.orthonormalized().get_rotation_quat()
		var error = angle(local, rotations[k])
		if error > worst_pose:
			worst_pose = error
		if error > POSE_TOLERANCE:
			fail("%s: bone %s is %g rad from the library's rotation" % [gaze.get_path(), skeleton.get_bone_name(bones[k]), error])
	# The onlookers stare at the facade point (an explicit point: get_gaze_target gives
	# their attention's node, which their eyes leave for the point).
	if demo.onlookers.has(gaze):
		if crowd.is_holding(gaze):
			onlooker_frames += 1
			check_eyes(gaze, bones, demo.FACADE_POINT, "the facade point")
		return
	# A glance where the onlookers stare (gaze following wins over attention).
	var following = crowd.get_following(gaze)
	if following != null:
		followers[gaze.get_instance_id()] = true
		if following.distance_to(demo.FACADE_POINT) > 1e-3:
			fail("%s follows a gaze to %s, not to the facade point" % [gaze.get_path(), following])
		# (Its eyes are not checked: a walker may glance at a point beyond what its joints
		# reach, and then holds the gaze short of it.)
		return
	# The eyes' target: from attention, or an explicit one (a node).
	var target = crowd.get_gaze_target(gaze)
	if target == null:
		return
	if crowd.is_attending(gaze):
		attending[gaze.get_instance_id()] = true
	targets_seen[target.get_instance_id()] = true
	if crowd.is_holding(gaze):
		check_eyes(gaze, bones, look_at_point(target), str(target.get_path()))


# Both eyes of a character whose gaze holds point at `point` within the tolerance.
func check_eyes(gaze, bones, point, what):
	var skeleton = gaze.get_parent()
	var place = skeleton.global_transform
	var key = skeleton.get_instance_id()
	var eyes = [bones.size() - 2, bones.size() - 1]   # the chain ends with both eyes
	if not eye_forward.has(key):
		var forwards = []
		for k in eyes:
			forwards.append(rest_global(skeleton, bones[k]).basis.inverse().xform(Vector3.BACK).normalized())
		eye_forward[key] = forwards
	for e in range(2):
		var k = eyes[e]
		var eye = place * skeleton.get_bone_global_pose(bones[k])
		var forward = (eye.basis.xform(eye_forward[key][e])).normalized()
		var to_target = (point - eye.origin).normalized()
		var degrees = rad2deg(acos(clamp(forward.dot(to_target), -1.0, 1.0)))
		eye_samples += 1
		if degrees > worst_eye:
			worst_eye = degrees
			worst_eye_where = "%s looking at %s" % [gaze.get_path(), what]
		if degrees > EYE_TOLERANCE_DEGREES:
			fail("%s: eye %d is %.2f degrees off %s" % [gaze.get_path(), e, degrees, what])


func finish():
	print("CROWDGAZE CHECK frames=%d characters_attending=%d targets=%d eye_samples=%d faded_frames=%d" % [frames, attending.size(), targets_seen.size(), eye_samples, faded_frames])
	print("CROWDGAZE CHECK onlooker_frames=%d followers=%d followed_gaze_signals=%d" % [onlooker_frames, followers.size(), demo.followed])
	print("CROWDGAZE CHECK max_pose_error_rad=%.9f max_eye_angle_deg=%.4f (%s)" % [worst_pose, worst_eye, worst_eye_where])
	if eye_samples == 0 or attending.size() < 3:
		fail("too few characters attended (%d) to check the eyes" % attending.size())
	if onlooker_frames < 300:
		fail("the onlookers' gaze held on the facade point for %d frames" % onlooker_frames)
	if followers.empty() or demo.followed == 0:
		fail("nobody followed the onlookers' gaze (%d followers, %d signals)" % [followers.size(), demo.followed])
	if faded_frames < 30:
		fail("the fading bystander's gaze was below full influence for %d frames" % faded_frames)
	for failure in failures:
		print("CROWDGAZE CHECK FAILURE " + failure)
	if failures.empty():
		print("CROWDGAZE CHECK PASSED")
		get_tree().quit(0)
	else:
		print("CROWDGAZE CHECK FAILED")
		get_tree().quit(1)
