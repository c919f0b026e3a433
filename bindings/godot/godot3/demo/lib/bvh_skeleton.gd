# A Godot Skeleton built from the hierarchy of a BVH clip (its joint names, parents and
# offsets; the motion is not used), turned to Godot's axes (Y up, facing +Z, metres), with
# two eye bones added under the head. Every bone's rest is rotated so that its Y axis runs
# along the bone, as imported rigs have: crowdgaze must not assume identity rests.
#
# Also a skinned mesh for it (boxes along the bones, a head, eyes with pupils, a nose), each
# vertex bound rigidly to one bone, so that heads and eyes turn with their bones.
extends Reference

const EYE_RADIUS = 0.024
const PUPIL_RADIUS = 0.0125

var names = []       # bone names
var parents = []     # parent index, -1 for the root
var positions = []   # rest positions in skeleton space (metres, Y up, facing +Z)
var globals = []     # rest global transforms (skeleton space)


# Reads the HIERARCHY of a BVH file and scales the skeleton to `height` metres, its feet on
# the ground. Returns an error string, or "" on success.
# Loads `file` (e.g. "bvh/zombie.bvh") from the shared data directory: CROWDGAZE_DATA, or
# ../shared/data beside the repository. Returns "" or what went wrong, as load_bvh does.
func load_shared(file, height):
	var data = OS.get_environment("CROWDGAZE_DATA")
	if data == "":
		data = ProjectSettings.globalize_path("res://").plus_file("../../../../../shared/data")
	return load_bvh(data.plus_file(file), height)


func load_bvh(path, height):
	var file = File.new()
	if file.open(path, File.READ) != OK:
		return "cannot read " + path
	var words = []
	while not file.eof_reached():
		var line = file.get_line().strip_edges()
		if line == "MOTION":
			break
		for word in line.split(" ", false):
			for w in word.split("\t", false):
				words.append(w)
	file.close()
	var offsets = []
	var stack = []
	var i = 0
	var pending_end = false
	while i < words.size():
		var word = words[i]
		if word == "ROOT" or word == "JOINT":
			names.append(words[i + 1])
			parents.append(stack.back() if stack.size() > 0 else -1)
			offsets.append(Vector3.ZERO)
			i += 2
		elif word == "End":
			pending_end = true
			i += 2
		elif word == "{":
			stack.append(-2 if pending_end else names.size() - 1)
			i += 1
		elif word == "}":
			stack.pop_back()
			pending_end = false
			i += 1
		elif word == "OFFSET":
			if not pending_end:
				var x = float(words[i + 1])
				var y = float(words[i + 2])
				var z = float(words[i + 3])
				# BVH: Z up, facing -Y. Godot: Y up, facing +Z.
				offsets[names.size() - 1] = Vector3(x, z, -y)
			i += 4
		elif word == "CHANNELS":
			i += 2 + int(words[i + 1])
		else:
			i += 1
	# An End Site's "{" pushed -2: parents never point there (joints only nest in joints).
	if names.empty():
		return "no joints in " + path
	var raw = []
	for b in range(names.size()):
		var parent_position = raw[parents[b]] if parents[b] >= 0 else Vector3.ZERO
		raw.append(parent_position + offsets[b])
	var low = INF
	var top = -INF
	for p in raw:
		low = min(low, p.y)
		top = max(top, p.y)
	var head = names.find("Head")
	if head < 0:
		return "no Head joint in " + path
	# The head joint is the skull's base: the top of the head is about 0.2 m above it.
	var scale = (height - 0.2) / (raw[head].y - low)
	for p in raw:
		positions.append(Vector3(p.x * scale, (p.y - low) * scale, p.z * scale))
	# The eyes, in front of and above the skull's base.
	for side in [1.0, -1.0]:
		names.append("LeftEye" if side > 0 else "RightEye")
		parents.append(head)
		positions.append(positions[head] + Vector3(0.034 * side, 0.075, 0.1))
	compute_rests()
	return ""


# Adds an upper-lid bone over each eye (eyelid_upper_l, eyelid_upper_r, under the head, its
# pivot at the eye's centre), as rigs with lid bones have; the mesh then has lids on them.
func add_lids():
	var head = names.find("Head")
	for eye in ["LeftEye", "RightEye"]:
		names.append("eyelid_upper_l" if eye == "LeftEye" else "eyelid_upper_r")
		parents.append(head)
		positions.append(positions[names.find(eye)])
	compute_rests()


# The rotation that takes +Y to `direction`.
static func along(direction):
	var d = direction.normalized()
	var axis = Vector3.UP.cross(d)
	if axis.length() < 1e-6:
		return Basis() if d.y > 0 else Basis(Vector3.RIGHT, PI)
	return Basis(axis.normalized(), Vector3.UP.angle_to(d))


# The first child of each bone (-1 for none).
func first_children():
	var children = []
	for b in range(names.size()):
		children.append(-1)
	for b in range(names.size()):
		var p = parents[b]
		if p >= 0 and children[p] < 0 and not is_face_bone(b):
			children[p] = b
	return children


# True for an eye or lid bone (they hang from the head without setting its direction).
func is_face_bone(b):
	return names[b].ends_with("Eye") or names[b].begins_with("eyelid")


# The rest global transforms: every bone's Y along the bone to its first child.
func compute_rests():
	var children = first_children()
	globals.clear()
	for b in range(names.size()):
		var basis
		if names[b].ends_with("Eye"):
			# An eye's rest: turned a little from the head's (its Y still up the head).
			basis = globals[parents[b]].basis * Basis(Vector3.UP, 0.3)
		elif children[b] >= 0:
			basis = along(positions[children[b]] - positions[b])
		elif parents[b] >= 0:
			basis = globals[parents[b]].basis
		else:
			basis = Basis()
		globals.append(Transform(basis, positions[b]))


# Adds the bones to `skeleton` with their rests.
func build(skeleton):
	for b in range(names.size()):
		skeleton.add_bone(names[b])
		skeleton.set_bone_parent(b, parents[b])
		var rest = globals[b]
		if parents[b] >= 0:
			rest = globals[parents[b]].affine_inverse() * globals[b]
		skeleton.set_bone_rest(b, rest)


# A bone's axis in its own frame for a skeleton-space axis (its rest frame).
func local_axis(bone, axis):
	return globals[bone].basis.inverse().xform(axis).normalized()


# ---- the mesh -------------------------------------------------------------------------

var _tool


func _vertex(position, normal, color, bone):
	_tool.add_color(color)
	_tool.add_normal(normal)
	_tool.add_bones(PoolIntArray([bone, 0, 0, 0]))
	_tool.add_weights(PoolRealArray([1.0, 0.0, 0.0, 0.0]))
	_tool.add_vertex(position)


# A box of `width` x `depth` from `a` to `b` (skeleton space), bound to `bone`.
func _box(a, b, width, depth, color, bone):
	var up = (b - a)
	var basis = along(up)
	var x = basis.x * width * 0.5
	var z = basis.z * depth * 0.5
	var corners = [a - x - z, a + x - z, a + x + z, a - x + z, b - x - z, b + x - z, b + x + z, b - x + z]
	var faces = [[0, 1, 2, 3, -basis.y], [7, 6, 5, 4, basis.y], [0, 4, 5, 1, -basis.z],
		[1, 5, 6, 2, basis.x], [2, 6, 7, 3, basis.z], [3, 7, 4, 0, -basis.x]]
	for f in faces:
		for k in [0, 1, 2, 0, 2, 3]:
			_vertex(corners[f[k]], f[4], color, bone)


# A sphere (a UV sphere of `rings` rings) at `center`, bound to `bone`.
func _sphere(center, radius, color, bone, rings = 8, scale = Vector3.ONE):
	var segments = rings * 2
	for r in range(rings):
		var t0 = PI * r / rings
		var t1 = PI * (r + 1) / rings
		for s in range(segments):
			var p0 = TAU * s / segments
			var p1 = TAU * (s + 1) / segments
			var quad = [Vector3(sin(t0) * cos(p0), cos(t0), sin(t0) * sin(p0)),
				Vector3(sin(t1) * cos(p0), cos(t1), sin(t1) * sin(p0)),
				Vector3(sin(t1) * cos(p1), cos(t1), sin(t1) * sin(p1)),
				Vector3(sin(t0) * cos(p1), cos(t0), sin(t0) * sin(p1))]
			for k in [0, 2, 1, 0, 3, 2]:
				var n = quad[k]
				_vertex(center + n * radius * scale, (n / scale).normalized(), color, bone)


func _width(name):
	if name.begins_with("Spine") or name == "Hips":
		return [0.3, 0.2]
	if name.ends_with("UpLeg"):
		return [0.13, 0.13]
	if name.ends_with("Leg"):
		return [0.1, 0.1]
	if name.ends_with("Foot"):
		return [0.09, 0.09]
	if name.ends_with("Arm") and not name.ends_with("ForeArm"):
		return [0.085, 0.085]
	if name.ends_with("ForeArm"):
		return [0.07, 0.07]
	if name == "Neck":
		return [0.08, 0.08]
	if name.ends_with("Shoulder"):
		return [0.1, 0.1]
	return [0.06, 0.05]


# The skinned mesh: `shirt` and `trousers` colours.
func mesh(shirt, trousers):
	var skin = Color(0.87, 0.68, 0.55)
	var dark = Color(0.12, 0.1, 0.1)
	_tool = SurfaceTool.new()
	_tool.begin(Mesh.PRIMITIVE_TRIANGLES)
	for b in range(names.size()):
		var p = parents[b]
		if p < 0 or is_face_bone(b):
			continue
		var name = names[p]
		if name == "Head":
			continue
		var size = _width(name)
		var color = skin
		if name.begins_with("Spine") or name == "Hips" or name.ends_with("Shoulder") or (name.ends_with("Arm") and not name.ends_with("ForeArm")):
			color = shirt
		elif name.ends_with("UpLeg") or name.ends_with("Leg"):
			color = trousers
		elif name.ends_with("Foot") or name.ends_with("ToeBase"):
			color = dark
		_box(positions[p], positions[b], size[0], size[1], color, p)
	var head = names.find("Head")
	var h = positions[head]
	_sphere(h + Vector3(0, 0.09, 0.01), 0.105, skin, head, 10, Vector3(0.92, 1.1, 1.0))
	_sphere(h + Vector3(0, 0.17, -0.035), 0.11, dark, head, 8, Vector3(0.97, 0.7, 1.0))
	_box(h + Vector3(0, 0.05, 0.1), h + Vector3(0, 0.05, 0.16), 0.035, 0.04, skin.darkened(0.15), head)
	for eye in [names.find("LeftEye"), names.find("RightEye")]:
		var e = positions[eye]
		_sphere(e, EYE_RADIUS, Color(0.97, 0.97, 0.97), eye, 8)
		_sphere(e + Vector3(0, 0, EYE_RADIUS * 0.75), PUPIL_RADIUS, Color(0.05, 0.05, 0.1), eye, 6)
	# Upper lids: a flattened shell over each eye's top, turning down over it in a blink.
	for lid in [names.find("eyelid_upper_l"), names.find("eyelid_upper_r")]:
		if lid >= 0:
			var e = positions[lid]
			_sphere(e + Vector3(0, EYE_RADIUS * 0.8, 0.004), EYE_RADIUS * 1.12, skin.darkened(0.1), lid, 8, Vector3(1.0, 0.55, 1.0))
	var result = _tool.commit()
	_tool = null
	var material = SpatialMaterial.new()
	material.vertex_color_use_as_albedo = true
	material.roughness = 0.8
	result.surface_set_material(0, material)
	return result
