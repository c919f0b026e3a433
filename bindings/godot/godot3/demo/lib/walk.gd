# A procedural walk for the demo's skeletons: legs and arms swing with a phase that advances
# with the distance walked, the hips sway about up and the spine turns back against them
# (those two are under the gaze: the addon reads them as the base pose), arms hang down.
# Standing people breathe. Poses are Godot 3's: rotations relative to each bone's rest.
extends Reference

const STRIDE = 1.4   # metres per walk cycle

var bones = {}       # name -> index
var axes = {}        # name -> [local X, local Y, local Z] (skeleton axes in the bone's frame)


func _init(builder):
	for b in range(builder.names.size()):
		var name = builder.names[b]
		bones[name] = b
		axes[name] = [builder.local_axis(b, Vector3.RIGHT), builder.local_axis(b, Vector3.UP), builder.local_axis(b, Vector3.BACK)]


# A rotation of bone `name` about the skeleton's X, Y and Z axes (radians, in that order
# applied last to first: Z, then Y, then X).
func turn(name, x, y, z):
	var a = axes[name]
	return Transform(Basis(a[0], x) * Basis(a[1], y) * Basis(a[2], z), Vector3.ZERO)


func pose(person, delta, time):
	var skeleton = person.skeleton
	var speed = person.speed
	person.phase = fmod(person.phase + delta * speed / STRIDE * TAU, TAU)
	var s = sin(person.phase)
	var c = cos(person.phase)
	var amount = clamp(speed / 1.2, 0.0, 1.0)
	var breathe = sin(time * 1.3 + person.phase) * 0.02
	skeleton.set_bone_pose(bones["Hips"], turn("Hips", 0.0, 0.09 * s * amount, 0.0))
	skeleton.set_bone_pose(bones["Spine"], turn("Spine", 0.04 * amount + breathe, -0.07 * s * amount, 0.0))
	skeleton.set_bone_pose(bones["Spine2"], turn("Spine2", breathe, -0.03 * s * amount, 0.0))
	skeleton.set_bone_pose(bones["LeftUpLeg"], turn("LeftUpLeg", -0.45 * s * amount, 0.0, 0.0))
	skeleton.set_bone_pose(bones["RightUpLeg"], turn("RightUpLeg", 0.45 * s * amount, 0.0, 0.0))
	skeleton.set_bone_pose(bones["LeftLeg"], turn("LeftLeg", 0.6 * max(0.0, c) * amount, 0.0, 0.0))
	skeleton.set_bone_pose(bones["RightLeg"], turn("RightLeg", 0.6 * max(0.0, -c) * amount, 0.0, 0.0))
	skeleton.set_bone_pose(bones["LeftArm"], turn("LeftArm", 0.35 * s * amount, 0.0, -1.3))
	skeleton.set_bone_pose(bones["RightArm"], turn("RightArm", -0.35 * s * amount, 0.0, 1.3))
	skeleton.set_bone_pose(bones["LeftForeArm"], turn("LeftForeArm", -0.3, 0.0, 0.0))
	skeleton.set_bone_pose(bones["RightForeArm"], turn("RightForeArm", -0.3, 0.0, 0.0))
