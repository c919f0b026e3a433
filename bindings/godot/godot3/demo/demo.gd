# The crowdgaze demo for Godot 3.2: people walking the UCY (or ETH) trajectories, a few
# bystanders and scene objects, and the camera as the viewer. Every character is a Skeleton
# built from the shared BVH clip's hierarchy, with a CrowdGazeCharacter child; one CrowdGaze
# node owns the crowd. The walk is animated here (legs, arms, a swaying spine): the addon
# reads that pose as the base under the gaze.
#
# Environment (all optional):
#   CROWDGAZE_DATA        the shared data directory (default: ../shared beside the repository)
#   CROWDGAZE_TRAJECTORY  the trajectory file in it (default pedestrians/ucy_zara01.csv)
#   CROWDGAZE_MODE        "" (run), check (check.gd's checks, then quit), render (save PNG
#                         frames to CROWDGAZE_FRAMES), bench (CROWDGAZE_BENCH characters,
#                         CROWDGAZE_ADDON=0 for none, prints the frame times)
#   CROWDGAZE_SECONDS     game seconds before quitting in those modes (default 20)
extends Spatial

const Builder = preload("res://lib/bvh_skeleton.gd")
const Trajectories = preload("res://lib/trajectories.gd")
const Walk = preload("res://lib/walk.gd")
const CharacterScript = preload("res://addons/crowdgaze/CrowdGazeCharacter.gdns")
const TargetScript = preload("res://addons/crowdgaze/GazeTarget.gdns")
const Check = preload("res://check.gd")
const PALETTES = [
	[Color(0.16, 0.35, 0.75), Color(0.2, 0.2, 0.25)],
	[Color(0.8, 0.25, 0.2), Color(0.25, 0.22, 0.2)],
	[Color(0.2, 0.6, 0.3), Color(0.3, 0.3, 0.35)],
	[Color(0.9, 0.7, 0.2), Color(0.15, 0.2, 0.35)],
	[Color(0.55, 0.3, 0.65), Color(0.35, 0.3, 0.25)],
	[Color(0.9, 0.9, 0.9), Color(0.2, 0.25, 0.45)],
]

var mode = ""
var seconds = 20.0
var frames_dir = ""
var with_addon = true
var with_mesh = true
var builder
var walk
var meshes = []
var trajectories
var start_time = 0.0
var center = Vector2.ZERO
var time = 0.0
var frame = 0
var people = {}       # track id -> person
var standing = []     # persons who do not walk
var bench_frames = []
var chatting = []     # the chatting pair's CrowdGazeCharacter nodes
var fading = null     # the bystander whose gaze fades out and in
var onlookers = []    # the group staring up at the facade (CrowdGazeCharacter nodes)
var followed = 0      # character_followed_gaze signals received
var last_ticks = 0

const FACADE_POINT = Vector3(2.5, 7.0, -12.0)   # what the onlookers stare at

onready var crowd = $CrowdGaze


func _ready():
	mode = OS.get_environment("CROWDGAZE_MODE")
	if OS.get_environment("CROWDGAZE_SECONDS") != "":
		seconds = float(OS.get_environment("CROWDGAZE_SECONDS"))
	frames_dir = OS.get_environment("CROWDGAZE_FRAMES")
	with_addon = OS.get_environment("CROWDGAZE_ADDON") != "0"
	var data = OS.get_environment("CROWDGAZE_DATA")
	if data == "":
		data = ProjectSettings.globalize_path("res://").plus_file("../../../../../shared/data")
	builder = Builder.new()
	var error = builder.load_bvh(data.plus_file("bvh/wave_hello.bvh"), 1.75)
	if error != "":
		fail(error)
		return
	walk = Walk.new(builder)
	if mode == "bench":
		with_mesh = false
		if not with_addon:
			crowd.free()
			crowd = null
		elif OS.get_environment("CROWDGAZE_ATTENTION_PERIOD") != "":
			# Settings are read when the crowd is made, as the node enters the tree.
			remove_child(crowd)
			crowd.attention_period = int(OS.get_environment("CROWDGAZE_ATTENTION_PERIOD"))
			add_child(crowd)
		setup_bench(int(OS.get_environment("CROWDGAZE_BENCH")))
		return
	# Gaze following (read when the crowd is made, so the crowd is made again with it):
	# passers-by may glance where the onlookers stare.
	remove_child(crowd)
	crowd.gaze_following = true
	add_child(crowd)
	crowd.connect("character_followed_gaze", self, "_on_followed_gaze")
	# Upper-lid bones (and lids on the mesh): the addon turns them with the eyelids.
	builder.add_lids()
	for palette in PALETTES:
		meshes.append(builder.mesh(palette[0], palette[1]))
	var file = OS.get_environment("CROWDGAZE_TRAJECTORY")
	trajectories = Trajectories.new()
	error = trajectories.load_csv(data.plus_file(file if file != "" else "pedestrians/ucy_zara01.csv"))
	if error != "":
		fail(error)
		return
	start_time = trajectories.busiest_start(seconds)
	setup_scene()
	if mode == "check":
		var check = Check.new()
		check.name = "Check"
		check.demo = self
		add_child(check)


func fail(message):
	push_error("demo: " + message)
	print("CROWDGAZE DEMO FAILED: " + message)
	get_tree().quit(1)


# The middle of the people present during the window.
func window_center():
	var sum = Vector2.ZERO
	var count = 0
	var t = start_time
	while t <= start_time + seconds:
		for id in trajectories.tracks:
			var p = Trajectories.sample(trajectories.tracks[id], t)
			if p != null:
				sum += p
				count += 1
		t += 1.0
	return sum / max(count, 1)


# Ground point of a trajectory position: x along X, y along -Z, the window's centre at 0.
func ground(point):
	return Vector3(point.x - center.x, 0.0, -(point.y - center.y))


func setup_scene():
	center = window_center()
	# Bystanders beside the walkway, and scene objects to look at.
	var spots = [[Vector3(-3.2, 0, 1.8), 2.08], [Vector3(3.0, 0, 2.2), -2.2], [Vector3(3.4, 0, -2.6), -1.2], [Vector3(-3.6, 0, -1.8), 1.4]]
	for k in range(spots.size()):
		standing.append(make_person(spots[k][0], spots[k][1], k % PALETTES.size(), "Bystander%d" % k))
	# Two people chatting in front of the camera, half turned towards the street: a
	# conversation, whose members look at each other (more at whoever talks; they take
	# turns).
	var left = make_person(Vector3(-0.75, 0, 4.8), PI / 2 - 0.6, 3, "ChatLeft")
	var right = make_person(Vector3(0.75, 0, 4.8), -PI / 2 + 0.6, 5, "ChatRight")
	standing.append(left)
	standing.append(right)
	if with_addon:
		var a = left.skeleton.get_node("Gaze")
		var b = right.skeleton.get_node("Gaze")
		if crowd.set_conversation([a, b]) < 0:
			fail("the chatting pair's conversation was not formed")
		a.talking = true
		chatting = [a, b]
		# One bystander's gaze fades out and back in (see update_controls).
		fading = standing[0].skeleton.get_node("Gaze")
		fading.influence_fade_time = 1.5
	# A group stopped by the walkway, staring up at a point on a facade: a cue that
	# passers-by may follow (gaze following).
	var group = [[Vector3(1.6, 0, -3.6), PI - 0.3], [Vector3(2.3, 0, -3.9), PI - 0.1], [Vector3(1.9, 0, -4.5), PI + 0.2]]
	for k in range(group.size()):
		var onlooker = make_person(group[k][0], group[k][1], (k + 2) % PALETTES.size(), "Onlooker%d" % k)
		standing.append(onlooker)
		if with_addon:
			var gaze = onlooker.skeleton.get_node("Gaze")
			if not crowd.set_gaze_target(gaze, FACADE_POINT):
				fail("an onlooker's gaze target was refused")
			onlookers.append(gaze)
	add_target("Kiosk", Vector3(-3.8, 0, 3.6), Color(0.85, 0.15, 0.15), 1.9, 2.0)
	add_target("Sign", Vector3(3.8, 0, 1.4), Color(0.95, 0.8, 0.1), 2.2, 2.0)
	add_target("Fountain", Vector3(-4.2, 0, 2.0), Color(0.2, 0.55, 0.9), 1.0, 1.5)
	update_people(0.0)


func make_person(position, heading, palette, name):
	var root = Spatial.new()
	root.name = name
	var skeleton = Skeleton.new()
	skeleton.name = "Skeleton"
	builder.build(skeleton)
	root.add_child(skeleton)
	if with_mesh:
		var body = MeshInstance.new()
		body.name = "Body"
		body.mesh = meshes[palette]
		skeleton.add_child(body)
		body.skeleton = NodePath("..")
	if with_addon:
		var gaze = CharacterScript.new()
		gaze.name = "Gaze"
		skeleton.add_child(gaze)
	root.transform = Transform(Basis(Vector3.UP, heading), position)
	add_child(root)
	return {"root": root, "skeleton": skeleton, "phase": randf() * TAU, "heading": heading, "speed": 0.0}


func add_target(name, position, color, height, impact):
	var node = TargetScript.new() if with_addon else Spatial.new()
	node.name = name
	if with_addon:
		node.look_at_height = height
		node.impact = impact
	var post = MeshInstance.new()
	var mesh = CylinderMesh.new()
	mesh.top_radius = 0.12
	mesh.bottom_radius = 0.16
	mesh.height = height
	post.mesh = mesh
	post.translation = Vector3(0, height * 0.5, 0)
	var material = SpatialMaterial.new()
	material.albedo_color = color
	post.material_override = material
	node.add_child(post)
	var top = MeshInstance.new()
	var ball = SphereMesh.new()
	ball.radius = 0.25
	ball.height = 0.5
	top.mesh = ball
	top.translation = Vector3(0, height, 0)
	top.material_override = material
	node.add_child(top)
	node.translation = position
	add_child(node)


# The chatting pair take turns talking (4 s each); the fading bystander's gaze fades out
# at 5 s and back in at 11 s (its animation shows through in between).
func update_controls():
	if chatting.empty():
		return
	var turn = int(time / 4.0) % 2 == 0
	chatting[0].talking = turn
	chatting[1].talking = not turn
	fading.active = time < 5.0 or time >= 11.0


func _on_followed_gaze(_character, _point):
	followed += 1


# People enter when their track begins and leave (freed at once) when it ends.
func update_people(delta):
	var t = start_time + time
	for id in trajectories.tracks:
		var track = trajectories.tracks[id]
		var point = Trajectories.sample(track, t)
		if point == null:
			if people.has(id):
				people[id].root.free()
				people.erase(id)
			continue
		var position = ground(point)
		var ahead = Trajectories.sample(track, t + 0.4)
		var behind = Trajectories.sample(track, t - 0.4)
		var velocity = Vector3.ZERO
		if ahead != null and behind != null:
			velocity = (ground(ahead) - ground(behind)) / 0.8
		if not people.has(id):
			var heading = atan2(velocity.x, velocity.z) if velocity.length() > 0.1 else 0.0
			people[id] = make_person(position, heading, id % PALETTES.size(), "Person%d" % id)
		var person = people[id]
		var speed = velocity.length()
		if speed > 0.25:
			person.heading = lerp_angle(person.heading, atan2(velocity.x, velocity.z), min(1.0, delta * 6.0))
		person.speed = speed
		person.root.transform = Transform(Basis(Vector3.UP, person.heading), position)
		walk.pose(person, delta, time)
	for person in standing:
		person.speed = 0.0
		walk.pose(person, delta, time)


func _process(delta):
	if mode == "bench":
		bench_frame(delta)
		return
	if trajectories == null:
		return
	time += delta
	frame += 1
	update_people(delta)
	update_controls()
	if mode == "render" and frames_dir != "" and frame % 10 == 0:
		var image = get_viewport().get_texture().get_data()
		image.flip_y()
		image.save_png(frames_dir.plus_file("frame_%04d.png" % frame))
	if mode != "" and time >= seconds - 1e-6:
		if mode == "render":
			print("CROWDGAZE RENDER: %d frames in %s" % [frame / 10, frames_dir])
			get_tree().quit(0)
		elif mode != "check":
			get_tree().quit(0)


# ---- benchmark --------------------------------------------------------------------------

var bench = []


# `count` characters on a grid, each walking a circle, and a few targets.
func setup_bench(count):
	var side = int(ceil(sqrt(count)))
	for k in range(count):
		var position = Vector3((k % side) * 2.5, 0, (k / side) * 2.5)
		var person = make_person(position, 0.0, 0, "P%d" % k)
		person["center"] = position
		person["angle"] = randf() * TAU
		bench.append(person)
	for k in range(8):
		add_target("T%d" % k, Vector3(randf() * side * 2.5, 0, randf() * side * 2.5), Color(1, 0, 0), 1.5, 2.0)
	last_ticks = OS.get_ticks_usec()


func bench_frame(delta):
	var now = OS.get_ticks_usec()
	frame += 1
	time += delta
	for person in bench:
		person.angle += delta * 0.8
		var offset = Vector3(cos(person.angle), 0, sin(person.angle)) * 0.8
		person.heading = atan2(-sin(person.angle), cos(person.angle))
		person.speed = 1.2
		person.root.transform = Transform(Basis(Vector3.UP, person.heading), person.center + offset)
		walk.pose(person, delta, time)
	if frame > 30:
		var parts = crowd.get_frame_parts_usec() if with_addon else Vector3.ZERO
		bench_frames.append([now - last_ticks, parts.x + parts.y + parts.z, parts])
	last_ticks = now
	if time >= seconds - 1e-6:
		var columns = [[], [], [], [], []]
		for sample in bench_frames:
			columns[0].append(sample[0] / 1000.0)
			columns[1].append(sample[1] / 1000.0)
			for k in range(3):
				columns[2 + k].append(sample[2][k] / 1000.0)
		var medians = []
		for column in columns:
			column.sort()
			medians.append(column[column.size() / 2])
		print("CROWDGAZE BENCH characters=%d addon=%d attention_period=%d frames=%d frame_ms=%.3f crowdgaze_ms=%.3f (read %.3f, step %.3f, write %.3f)" % [
			bench.size(), 1 if with_addon else 0, crowd.attention_period if with_addon else 0,
			columns[0].size(), medians[0], medians[1],
			medians[2], medians[3], medians[4]])
		get_tree().quit(0)
