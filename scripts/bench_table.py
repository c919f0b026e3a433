"""Prints the README's benchmark tables from criterion's results (medians of one run):
the crowd step with its baselines, then an engine's whole frame through the C API.

Usage: python3 scripts/bench_table.py TARGET/criterion
Every number is a criterion median from the same `scripts/bench` run; ratios compare
benchmarks of that run only.
"""

import json
import pathlib
import sys


def load(root):
    """{(group, function, value): (median ns per iteration, elements per iteration)}"""
    results = {}
    for path in root.glob("**/new/benchmark.json"):
        bench = json.loads(path.read_text())
        estimates = json.loads((path.parent / "estimates.json").read_text())
        elements = (bench.get("throughput") or {}).get("Elements", 1)
        key = (bench["group_id"], bench.get("function_id"), bench.get("value_str"))
        results[key] = (estimates["median"]["point_estimate"], elements)
    return results


def main():
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "target/criterion")
    results = load(root)
    if not results:
        sys.exit(f"no criterion results under {root}: run scripts/bench first")

    def per_element(group, function, value=None, elements=None):
        """Median µs per element (character-frame, or per `elements` if given)."""
        found = results.get((group, function, value))
        if found is None:
            return None
        median, count = found
        return median / 1000.0 / (elements or count)

    def show(value, digits=2):
        return "–" if value is None else f"{value:.{digits}f}"

    def ratio(slow, fast):
        return "–" if slow is None or fast is None else f"{slow / fast:.2f}×"

    print("Crowd step, plaza at 0.25 people/m² (µs per character-frame, criterion medians)")
    print()
    print("| characters | threads | attention | gaze IK | attention + gaze IK "
          "| all-pairs attention (baseline) | all-pairs / attention |")
    print("|---:|---:|---:|---:|---:|---:|---:|")
    step = {}
    for characters in ["1000", "10000", "100000"]:
        for threads in ["1", "2"]:
            cell = lambda part: per_element("attention", f"{part}_{threads}t", characters)
            attention, gaze, both = cell("attention"), cell("gaze_ik"), cell("step")
            all_pairs = cell("all_pairs")
            step[(characters, threads)] = both
            print(f"| {int(characters):,} | {threads} | {show(attention)} | {show(gaze)} "
                  f"| {show(both)} | {show(all_pairs)} | {ratio(all_pairs, attention)} |")
    print()
    lod = per_element("attention", "attention_lod4_1t", "10000")
    print(f"- Attention every 4th frame (level of detail), 10,000 characters, 1 thread: "
          f"{show(lod)} µs per character-frame.")
    for part, what in [("step", "Whole step"), ("gaze_ik", "Gaze IK")]:
        on = per_element("attention", f"{part}_blinks_on_1t", "10000")
        off = per_element("attention", f"{part}_blinks_off_1t", "10000")
        if on is not None and off is not None:
            print(f"- {what} with blinks and lids against without, 10,000 characters, "
                  f"1 thread: {on * 1000.0:.1f} against {off * 1000.0:.1f} ns per "
                  f"character-frame ({(on - off) * 1000.0:+.1f} ns).")
    alone = per_element("street", "step_alone_1t", "1000")
    talking = per_element("street", "step_conversations_1t", "1000")
    if alone is not None and talking is not None:
        print(f"- The street of 1,000 people, 1 thread: {talking * 1000.0:.1f} ns per "
              f"character-frame with a third of them in conversations, {alone * 1000.0:.1f} "
              f"without ({ratio(talking, alone)}).")
    for characters in ["1000", "10000", "100000"]:
        print(f"- 2 threads vs 1, attention + gaze IK, {int(characters):,} characters: "
              f"{ratio(step[(characters, '1')], step[(characters, '2')])} faster.")
    print(f"- 100,000 vs 1,000 characters per character-frame, 1 thread: "
          f"{ratio(step[('100000', '1')], step[('1000', '1')])}.")
    ik = per_element("gaze_ik", "update_batch, tracking, 1000 characters")
    jacobian = per_element("gaze_ik", "Jacobian DLS IK, tracking, 1000 characters")
    print(f"- Gaze IK alone (`GazeMotion::update_batch`, 10 joints, 1,000 characters "
          f"tracking): {show(ik, 3)} µs; Jacobian DLS IK baseline: {show(jacobian, 2)} µs "
          f"({ratio(jacobian, ik)} slower).")
    dlb = per_element("dlb_27_joints", None, "3")
    dib = per_element("dib_27_joints_p1e-6", None, "3")
    dib_coarse = per_element("dib_27_joints_p1e-3", None, "3")
    nalgebra = per_element("sclerp_27_joints_k2", "nalgebra_try_sclerp")
    ours = per_element("sclerp_27_joints_k2", "crowdgaze_sclerp")
    print(f"- Pose blending, 27 joints from 3 key poses (µs per pose): DLB {show(dlb, 3)}, "
          f"DIB at p = 1e−6 {show(dib)}, DIB at p = 1e−3 {show(dib_coarse)}; two keys "
          f"(ScLERP): crowdgaze {show(ours)} vs nalgebra {show(nalgebra)} "
          f"({ratio(nalgebra, ours)}).")
    state = root / "state_bytes_per_character.txt"
    if state.exists():
        print(f"- State per character (per-character arrays and its share of the scene "
              f"and grid): {state.read_text().strip()} bytes.")

    print()
    print("Engine frame through the C API (ns per character-frame, criterion medians)")
    print()
    print("| characters | threads | push_frame | step | read_gaze | read_joints | read_eyes "
          "| read_eyelids | whole frame | whole frame, reorder_period = 32 |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    parts = ["push", "step", "read_gaze", "read_joints", "read_eyes", "read_eyelids", "frame",
             "frame_reorder32"]
    for characters in ["1000", "10000", "100000"]:
        for threads in ["1", "2"]:
            cells = [per_element("frame", f"{part}_{threads}t", characters) for part in parts]
            ns = [None if cell is None else cell * 1000.0 for cell in cells]
            print(f"| {int(characters):,} | {threads} | "
                  + " | ".join(show(cell, 1) for cell in ns) + " |")
    print()
    # Each character's own skeleton through cg_rig: one line, every crowd size.
    rig = []
    for characters in ["1000", "10000", "100000"]:
        base = per_element("frame", "rig_base_pose", characters)
        write = per_element("frame", "rig_write_joints", characters)
        if base is not None and write is not None:
            rig.append(f"{base * 1000.0:.1f} and {write * 1000.0:.1f} ns at "
                       f"{int(characters):,}")
    if rig:
        print("- A 65-bone Mixamo skeleton per character, 1 thread: cg_rig_base_pose and "
              "cg_rig_write_joints take " + "; ".join(rig) + " characters (per character).")
    # Two benchmarks of the same frame compared, one line per crowd size.
    pairs = [
        ("push_1t", "push_ranged_2t", "Push, {n} characters: {a:.1f} ns in one "
         "cg_crowd_push_frame, {b:.1f} ns in two parts pushed from two threads ({r})."),
        ("step_unread_1t", "step_1t", "Step, 1 thread, {n} characters: {a:.1f} ns when "
         "nobody reads its outputs, {b:.1f} ns when they are read and it publishes them "
         "({r})."),
    ]
    for first, second, line in pairs:
        for characters in ["1000", "10000", "100000"]:
            a = per_element("frame", first, characters)
            b = per_element("frame", second, characters)
            if a is not None and b is not None:
                r = ratio(a, b) if first == "push_1t" else ratio(b, a)
                print("- " + line.format(n=f"{int(characters):,}", a=a * 1000.0,
                                         b=b * 1000.0, r=r))

if __name__ == "__main__":
    main()
