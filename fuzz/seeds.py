#!/usr/bin/env python3
"""Writes the seed corpus of the api_calls fuzz target to fuzz/corpus/api_calls/seed-*.

Each seed is a list of operations `[op, n, n argument bytes]` (see fuzz/src/api/mod.rs):
a few scenes built with ordinary arguments (zero bytes are the ordinary choice), and
random sequences. Op numbers are read from the table in fuzz/src/api/ops.rs, so the seeds
follow it. Deterministic: rerunning rewrites the same files. Regression inputs (crash-*)
are left alone.
"""
import pathlib
import random
import re

root = pathlib.Path(__file__).resolve().parent
names = re.findall(r'^\s*\("(\w+)", ', (root / "src/api/ops.rs").read_text(), re.M)
OP = {name: index for index, name in enumerate(names)}


def op(name, *args):
    return bytes([OP[name], len(args), *args])


def character(x, z, model=0):
    # struct_size, position (x, y, z), heading, impact, attention model (rare?, model)
    return op("add_character", 0, x, 0, z, 0, 0, 0, model)


def walk(frames):
    return b"".join(op("walk", n % 7) for n in range(frames))


def reads():
    return op("read_gaze", 0, 16) + op("read_joints", 0, 12) + op("read_eyes", 0, 12) + op(
        "read_joint_deltas", 3, 2
    ) + op("read_eyelids", 0, 12)


def crowd(count, model=0):
    return b"".join(character((8 * i) % 100, (24 * i) % 80, model) for i in range(count))


def street():
    return crowd(6) + op("add_object", 0, 16, 0, 8) + op("set_viewer", 0, 0, 20) + walk(90) + reads()


def models():
    return crowd(3, 1) + crowd(3, 2) + op("add_object", 0, 4, 0, 4) + walk(60) + reads() + op("score", 1, 0, 2, 0)


def offline():
    return crowd(4) + op("add_object", 0, 8, 0, 0) + walk(45) + op("plan") + b"".join(
        op("step") for _ in range(20)
    ) + op("read_constraints", 0, 0, 5) + reads() + op("add_character") + op("clear_plan") + walk(5)


def targets():
    return crowd(3) + op("set_gaze_target", 0, 0, 0, 0, 0, 0, 1, 8, 0, 8) + op(
        "set_gaze_target", 1, 0, 0, 0, 1, 0, 0, 2
    ) + walk(40) + op("clear_gaze_target", 0, 0) + walk(20) + reads()


def poses():
    return crowd(2) + op("set_base_pose", 0, 0, 0, 4, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0) + op(
        "set_base_poses", 2, 0, 0, 1
    ) + walk(30) + reads()


def parameters():
    return crowd(3) + op("set_character_params", 0, 2, 4, 64, 5, 1) + op("set_impact", 1, 0, 0, 60) + op(
        "set_attention_period", 2, 0, 0, 4
    ) + walk(40) + op("get_character_params") + op("get_config") + op("character_count")


def lod():
    # A crowd with level of detail by distance: attention period 3, lod 5 m.
    return op("crowd_create", 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 3, 2, 0, 0, 3, 3, 3, 160, 20, 3) + crowd(8) + op(
        "set_viewer", 0, 0, 0
    ) + walk(60) + reads()


def ranged():
    # Steps split into ranges (ordinary dt, up to four ranges), between ordinary frames.
    steps = b"".join(op("ranged_step", 0, 0, 4, 0, n, 0, 8, 0, 20, 0, 40, 0, 9) + walk(2) for n in range(20))
    return crowd(6) + walk(5) + steps + reads()


def pushes():
    # Frames pushed in parts into a crowd without recording (the first crowd records),
    # between ordinary frames: two parts of up to three states, ids picked by the bytes.
    create = op("crowd_create", 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 3, 0)
    parts = b"".join(
        op("ranged_push", 0, 2, 3, 0, n % 6, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 3, 0, (n + 1) % 6) + walk(1)
        for n in range(20)
    )
    return create + crowd(6) + walk(3) + parts + reads()


def blender(dib):
    config = op("blender_create", 0, 1, 2, 0, 0, 0, dib, 0, 0)
    # A rigid transform: (ordinary, angle, x, y, z).
    def pose(k):
        return [0, 8 * k, 4, 0, 8, 0, 4 * k, 0, 0, 8]

    keys = b"".join(op("set_key_pose", k, 0, *pose(k)) for k in range(3))
    frames = [byte for f in range(3) for byte in pose(f + 1)]
    clip = op("set_key_clip", 1, 0, 3, *frames, 0, 1)
    cameras = b"".join(op("add_camera", 0, a, 0, k) for k, a in enumerate([0, 16, 100, 200]))
    return config + keys + clip + cameras + op("weights") + op("evaluate", 0, 24)


def blends():
    return op("blend_dlb", 3, 0, 8, 0, 0, 0, 0, 16, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0) + op(
        "blend_dib", 0, 0, 2, 0, 40, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 3
    ) + op("blend_pose_dlb", 2, 3) + op("blend_pose_dib", 0, 0, 2, 2) + op("from_rt", 0, 8, 0, 0, 8, 8, 8) + op(
        "to_rt", 0, 8, 8, 8, 8
    ) + op("from_matrix", 16, 8, 0, 8) + op("to_matrix", 0, 8, 8, 8, 8) + op("camera_center", 100, 8, 0, 8, 8) + op(
        "chain_init", 4, 3
    ) + op("messages", 20)


def maxima():
    # A crowd whose recording is at its maximum (the create's last argument byte, rare):
    # CG_STATUS_OUT_OF_MEMORY, or a crowd that works where memory is overcommitted.
    create = op("crowd_create", *([0] * 20), 0xFF)
    return create + crowd(3) + walk(4) + reads()


def conversations():
    # Two groups of the first crowd's characters: live[0] and live[1], then live[2 .. 5];
    # the talker passes every second in the pair and every 2/3 s in the three. Then reads,
    # a member removed (the pair ends), the ended group removed, the other removed twice,
    # and a group of one refused.
    # set_conversation: count (0: 2 members, 1: 3), each id (0: a live one, its index).
    groups = op("set_conversation", 0, 0, 0, 0, 1) + op("set_conversation", 1, 0, 2, 0, 3, 0, 4)
    # walk: one float per live entity (0: its lane), then the byte of who talks.
    talks = b"".join(
        op("walk", 0, 0, 0, 0, 0, (1 << (f // 30 % 2)) | (1 << (2 + f // 20 % 3))) for f in range(90)
    )
    # get_conversation: the id (0: a live one, its index).
    asks = op("get_conversation", 0, 0) + op("get_conversation", 0, 3)
    ends = op("remove_entity", 0, 1) + walk(5) + op("remove_conversation", 0, 0) + op(
        "remove_conversation", 0, 1
    ) + op("remove_conversation", 0, 1) + op("set_conversation", 14, 1, 0, 2)
    return crowd(5) + groups + talks + asks + reads() + ends + asks + walk(5) + reads()


def following():
    # The street preset (the create's last byte, 6: following on) for 14 characters (byte 9:
    # 13), each with the street model (a rare model byte, then 3 as a u32); the first three
    # stare at a point up high (an overriding point target), the others walk past. Then each
    # character's following is read, one with its outputs NULL, and a starer is released.
    create = op("crowd_create", 0, *([0] * 8), 13, *([0] * 13), 6)
    people = b"".join(
        op("add_character", 0, (8 * i) % 100, 0, (24 * i) % 80, 0, 0, 0, 0xF0, 3, 0, 0, 0) for i in range(14)
    )
    stares = b"".join(op("set_gaze_target", 0, k, 0, 0, 0, 0, 0, 8, 100, 16) for k in range(3))
    asks = b"".join(op("read_following", 0, k) for k in range(14)) + op("read_following", 0, 5, 0, 0xF0)
    release = op("clear_gaze_target", 0, 0)
    return create + people + stares + walk(150) + asks + reads() + release + walk(60) + asks


def pauses():
    # Long steps on a crowd that blinks and talks: a time stamp's worth (1e7 s), 1e30 s and
    # the largest floats, whole and ranged (a rare dt byte, then the special value's index),
    # each followed by ordinary frames.
    groups = op("set_conversation", 0, 0, 0, 0, 1) + op("set_conversation", 1, 0, 2, 0, 3, 0, 4)
    long_steps = b"".join(
        op("step", 0xF0, 0xF0 + k) + walk(10) + op("ranged_step", 0xF0, 0xF0 + k, 2, 0, 0, 0, 3) + walk(10)
        for k in (11, 5, 3, 14)
    )
    return crowd(3) + crowd(3, 1) + crowd(2, 2) + groups + walk(30) + long_steps + reads()


def rigs():
    # rig_create: struct_size, bone count (0, 0: all 16 humanoid bones), then per bone a
    # name (0: the humanoid's; 13, i: NAMES[i]), a parent (0: the humanoid's), three noise
    # floats and a rotation (1: identity); then a NULL name?, bone_count, the three arrays
    # (0: given), rotations (1: given), units (0: 10; 14: 100), up and forward (0: detect),
    # a bone map (7, i: BONE_MAPS[i]) ... (see fuzz/src/api/rig_ops.rs).
    def bones(renamed=None):
        renamed = renamed or {}
        out = []
        for bone in range(16):
            name = [13, renamed[bone]] if bone in renamed else [0]
            out += name + [0, 0, 0, 0, 1]
        return out
    plain = op("rig_create", 0, 0, 0, *bones())
    # A VRM chest for Spine1, a non-ASCII bone for HeadTop_End, the neck mapped as spine,
    # centimetres.
    weird = op("rig_create", 0, 0, 0, *bones({2: 14, 13: 32}), 0, 0, 0, 0, 0, 1, 14, 0, 0, 7, 8)
    frames = b"".join(
        op("rig_base_pose", 0, 0, *[f % 5, 0, 0, 0] * 16) + op("rig_write_joints", 0, 0, *[1, f % 3, 0, 0] * 20)
        for f in range(12)
    )
    return plain + op("rig_report", 0, 80) + op("rig_chain") + op("rig_lists", 0, 0, 0, 0) + op(
        "rig_lists", 0, 0, 0, 1
    ) + frames + weird + op("rig_report", 0, 200) + frames + op("rig_chain", 0xF0, 0xF0, 2)


# The operations the random seeds draw from: those the table had when they were written, so
# that appending operations leaves the committed seeds byte for byte as they were.
RANDOM_OPS = names[: OP["get_conversation"] + 1]


def random_seed(rng):
    data = bytearray()
    for _ in range(rng.randrange(5, 60)):
        name = rng.choice(RANDOM_OPS)
        args = [rng.choice([0, 0, 0, 1, 2, 3, rng.randrange(256)]) for _ in range(rng.randrange(0, 24))]
        data += op(name, *args)
        if rng.randrange(4) == 0:
            data += walk(rng.randrange(1, 20))
    return bytes(data)


def main():
    out = root / "corpus" / "api_calls"
    out.mkdir(parents=True, exist_ok=True)
    for old in out.glob("seed-*"):
        old.unlink()
    seeds = {
        "street": street(),
        "models": models(),
        "offline": offline(),
        "targets": targets(),
        "poses": poses(),
        "parameters": parameters(),
        "lod": lod(),
        "pushes": pushes(),
        "ranged": ranged(),
        "blender-dlb": blender(0),
        "blender-dib": blender(1),
        "blends": blends(),
        "maxima": maxima(),
        "conversations": conversations(),
        "pauses": pauses(),
        "rigs": rigs(),
        "following": following(),
    }
    rng = random.Random(10)
    for index in range(30):
        seeds[f"random-{index:02}"] = random_seed(rng)
    for name, data in seeds.items():
        (out / f"seed-{name}").write_bytes(data)
    print(f"{len(seeds)} seeds, {sum(map(len, seeds.values()))} bytes in {out}")


if __name__ == "__main__":
    main()
