#!/usr/bin/env python3
"""Writes the fuzz targets' seed corpora, tools/fuzz/corpus/<target>/
(README.md here). Run from the repository's root after a Release build:

    python3 tools/fuzz/make_seeds.py build/rel/bitstep

scene: the shipped scenes as they are. replay: short golden replays with
their scene embedded (the replay target reads no scene files) and their
hash chain cut at the last input, plus a few written here (add_joint,
remove_joint, settings). settings: every settings object of the shipped
scenes and replays, and a few written here. snapshot: images that
`bitstep run --snapshot-at` writes of small scenes. packet: every packet
type, encoded as replay/session_codec.h lays them out, a state packet
carrying a snapshot image. capi: call sequences written here, in the
format tools/fuzz/capi_input.h describes.
"""
import json
import os
import re
import struct
import subprocess
import sys
import tempfile

ROOT = os.getcwd()
CORPUS = os.path.join(ROOT, "tools", "fuzz", "corpus")
SCENES = os.path.join(ROOT, "scenes")


def write(target, name, data):
    folder = os.path.join(CORPUS, target)
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, name), "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode())


def value_text(text, key):
    """The text of the value of the first `"key":` in `text`, verbatim (exact numbers)."""
    for m in re.finditer(r'"%s"\s*:\s*' % re.escape(key), text):
        try:
            _, end = json.JSONDecoder().raw_decode(text, m.end())
        except json.JSONDecodeError:  # inside a string
            continue
        return text[m.end():end]
    return None


def scenes():
    for name in sorted(os.listdir(SCENES)):
        if name.endswith(".json") and not name.endswith(".replay.json"):
            yield name, open(os.path.join(SCENES, name)).read()


REPLAYS = ["wall128.short", "playground.short", "pyramid20.short", "ragdolls.short", "bounce", "incline",
           "slide_stop", "sensors", "car_wall", "dominoes", "jenga", "spheres", "stack20", "pyramid20.sleep_motion",
           "bridge", "tables", "thrown", "sliders_motors"]


def replays():
    for stem in REPLAYS:
        text = open(os.path.join(SCENES, stem + ".replay.json")).read()
        data = json.loads(text)
        scene_name = data["scene"]
        scene_text = open(os.path.join(SCENES, scene_name)).read()
        text = text.replace('"scene": "%s"' % scene_name, '"scene": ' + scene_text.strip(), 1)
        last = max([i["step"] for i in data.get("inputs", [])] + [1])
        if last < data["steps"]:
            hashes = value_text(text, "hashes")
            kept = json.dumps(data["hashes"][:last])
            text = text.replace(hashes, kept, 1)
            text = re.sub(r'"steps"\s*:\s*\d+', '"steps": %d' % last, text, count=1)
        write("replay", stem + ".replay.json", text)
    chains = open(os.path.join(SCENES, "chains.json")).read().strip()
    write("replay", "add_joint.replay.json", """{"format": "bitstep-replay", "version": 1, "engine": "seed",
 "scene": %s, "settings": {"sleep": "motion", "pipeline": "guendelman"},
 "scene_hash": "0000000000000000", "steps": 4,
 "inputs": [
  {"step": 1, "type": "add_joint", "joint": {"type": "max_distance", "name": "rope", "body_a": 0, "body_b": 1,
   "local_anchor_a": [0, 0.25, 0], "anchor_b": [0, 1, 0], "length": "1/2"}},
  {"step": 2, "type": "add_joint", "joint": {"type": "hinge", "name": "h", "body_a": 2, "body_b": 3,
   "anchor": [0, 0, 0], "axis": [0, 0, 1], "limits": [-45, 45], "friction": 1}},
  {"step": 3, "type": "remove_joint", "joint": "rope"},
  {"step": 4, "type": "set_velocity", "body": 2, "linear": [1, 0, 0], "angular": ["raw:10000", 0, 0]},
  {"step": 4, "type": "wake", "body": 3}],
 "hashes": ["0000000000000001", "0000000000000002", "0000000000000003", "0000000000000004"]}
""" % chains)


def settings():
    seen = set()
    for name in sorted(os.listdir(SCENES)):
        if not name.endswith(".json"):
            continue
        text = open(os.path.join(SCENES, name)).read()
        value = value_text(text, "settings")
        if value and value not in seen:
            seen.add(value)
            write("settings", name.replace(".json", ".settings.json"), value)
    write("settings", "empty.json", "{}")
    write("settings", "sleep_still.json", '{"sleep": "still", "sleep_time": 2, "sleep_linear_tolerance": "1/100"}')
    write("settings", "all.json", json.dumps({
        "dt": "1/120", "gravity": ["0", "-9.81", "raw:0"], "velocity_iterations": 12, "position_iterations": "3", "held_velocity_iterations": 6, "substeps": 2,
        "penetration_slop": 0.005, "split_impulse_factor": 0.3, "max_push_out_speed": 2, "baumgarte": True,
        "baumgarte_factor": "1/5", "restitution_threshold": 1e0, "speculative_distance": 0.02,
        "max_linear_speed": 400, "max_angular_speed": 50, "warm_starting": False, "shock_propagation": True,
        "shock_iterations": 16, "pipeline": "guendelman", "sleep": "motion", "sleep_epsilon": 0.05,
        "sleep_bias": 0.96, "sleep_min_time": 0.5, "sleep_time": 1, "sleep_linear_tolerance": 0.05,
        "sleep_angular_tolerance": 0.1}))


# The fuzz snapshot target's own world (tools/fuzz/snapshot.cpp).
SMALL_SCENE = """{"format": "bitstep-scene", "version": 1,
  "bodies": [
    {"name": "ground", "type": "static", "position": [0, -1, 0], "shapes": [{"type": "box", "half_extents": [10, 1, 10]}]},
    {"name": "box", "position": [0, 0.5, 0], "shapes": [{"type": "box", "half_extents": [0.5, 0.5, 0.5]}]},
    {"name": "ball", "position": [0, 2, 0], "shapes": [{"type": "sphere", "radius": 0.5}]}],
  "joints": [{"type": "point", "body_a": "box", "body_b": "ball", "anchor": [0, 1.25, 0]}]}"""


def snapshots(bitstep):
    images = {}
    with tempfile.TemporaryDirectory() as tmp:
        small = os.path.join(tmp, "small.json")
        open(small, "w").write(SMALL_SCENE)
        runs = [("small_1", small, 1), ("small_30", small, 30), ("bounce_40", "scenes/bounce.json", 40),
                ("slide_stop_20", "scenes/slide_stop.json", 20), ("sensors_30", "scenes/sensors.json", 30),
                ("incline_20", "scenes/incline.json", 20), ("car_wall_10", "scenes/car_wall.json", 10),
                ("sliders_motors_30", "scenes/sliders_motors.json", 30), ("dice_45", "scenes/dice.json", 45),
                ("terrain_20", "scenes/terrain.json", 20), ("hills_20", "scenes/hills.json", 20)]
        for name, scene, step in runs:
            out = os.path.join(tmp, name + ".snapshot")
            subprocess.run([bitstep, "run", scene, "--steps", str(step + 1), "--snapshot-at", str(step), out],
                           check=True, stdout=subprocess.DEVNULL)
            images[name] = open(out, "rb").read()
            write("snapshot", name + ".snapshot", images[name])
    return images


def packet(kind, player, ack, tick, body, sequence=7):
    return b"bS" + bytes([3, kind]) + struct.pack("<I", sequence) + bytes([player]) + struct.pack("<qq", ack, tick) + body


def roster(*changes):  # (at, from, player, presence)
    return bytes([len(changes)]) + b"".join(struct.pack("<qqBB", *change) for change in changes)


def packets(images):
    inputs = [b"", b"\x01", b"left+jump", bytes(range(32))]
    write("packet", "inputs_0.bin", packet(0, 0, 0, 1, bytes([0]) + roster()))
    write("packet", "inputs_1.bin", packet(0, 1, 5, 6, bytes([1]) + struct.pack("<H", 1) + b"\x01" + roster()))
    body = bytes([len(inputs)]) + b"".join(struct.pack("<H", len(i)) + i for i in inputs)
    write("packet", "inputs_4.bin", packet(0, 3, -1, 1 << 40, body + roster()))
    write("packet", "inputs_roster.bin", packet(0, 0, 40, 41, body + roster((41, 38, 2, 0), (42, 42, 3, 1), (43, 43, 1, 2))))
    write("packet", "relay.bin", packet(3, 1, 5, 6, bytes([2]) + body))
    write("packet", "checksum.bin", packet(1, 2, 60, 60, struct.pack("<QBQQ", 0xfbe30ec9ec0eefda, 2, 1, 2)))
    state = images["small_1"]
    game = bytes([100, 100, 3, 0])  # a game's state: two health bars, two scores
    write("packet", "state.bin", packet(2, 1, 30, 30, struct.pack("<I", len(state)) + state +
                                        struct.pack("<I", len(game)) + game))
    write("packet", "state_empty.bin", packet(2, 0, 0, 0, struct.pack("<II", 0, 0)))
    write("packet", "join_state.bin", packet(4, 0, 30, 30, bytes([2]) +
                                            struct.pack("<HHQI", 0b0011, 0b1000, 0x3c0e9c78ac0b4f0f, len(state)) + state +
                                            struct.pack("<I", len(game)) + game))
    write("packet", "quality.bin", packet(6, 1, 40, 44, struct.pack("<qB", 300, 2) + struct.pack("<qqqq", 270, 3, -1, 0)))
    write("packet", "join_check.bin", packet(5, 1, 30, 30, bytes([2]) + struct.pack("<Q", 0xfbe30ec9ec0eefda)))
    write("packet", "refused.bin", b"bS" + bytes([3, 17, 2, 0, 2, 1, 2]) + struct.pack("<Q", 0x3c0e9c78ac0b4f0f) +
          bytes([0]))  # player 0 of a 2-player rollback match: another player count
    hellos = {"hello_rollback": (0, 2, 1, 2, 0), "hello_lockstep": (3, 4, 0, 0, 0), "hello_join": (2, 3, 1, 0, 1),
              "hello_watch": (3, 4, 0, 1, 2)}
    for name, (player, players, mode, delay, joining) in hellos.items():
        write("packet", name + ".bin", b"bS" + bytes([3, 16, player, players, mode, delay]) +
              struct.pack("<Q", 0x3c0e9c78ac0b4f0f) + bytes([joining]))


# --- capi: C API call sequences (tools/fuzz/capi_input.h) -------------------
CALLS = ["add_body_fragment", "add_body_text", "add_joint_fragment", "add_joint_text", "remove_body", "remove_joint",
         "set_velocity", "apply_impulse", "apply_force", "drive", "wake", "step", "save", "load", "save_state",
         "load_state", "get", "cast_ray", "find_body", "null_arguments", "recreate",
         "create_body_struct", "create_joint_struct", "read_all", "character"]
NAMES = ["ground", "box", "ball", "chassis", "crate", "pill", "pair", "sensor", "wall", ""]
TEXTS = ["0", "1", "-1", "0.5", "1/60", "16000", "16000.000001", "-16001", "50", "50.01",
         "0.01", "0.009", "100000", "100001", "1e9", "1e300", "-1e300", "nan", "inf", "-inf",
         "1e-300", "\"7\"", "null", "[]", "-0", "2147483647", "2147483648", "0x10", "", "1/0",
         "500", "500.00001", "100", "-100.5", "1e6", "1000000.1", "90", "360", "1e-9", "3"]
BOUNDS = [0, 1, 100, 500, 16000, 65536, 131072, 524288, 1000000, 1048576, 2147483647]


def call(name, *args):
    return bytes([CALLS.index(name)]) + b"".join(args)


def known(k):  # the k-th handle the sequence has seen
    return bytes([0, k])


def made_up(index, generation):
    return bytes([0x80, index, generation])


def units(v):
    return bytes([0, v & 0xff])


def raw(r):
    return bytes([1]) + struct.pack("<q", r)


def edge(bound, delta=0, negative=False):
    return bytes([2, BOUNDS.index(bound) | (0x80 if negative else 0), delta & 0xff])


def double(d):
    return bytes([3]) + struct.pack("<d", d)


def text(t):
    return bytes([4, TEXTS.index(t)])


def fragment(index, texts, cut=0):
    return bytes([index]) + bytes(TEXTS.index(t) for t in texts) + bytes([cut])


def find(name):
    return call("find_body", bytes([NAMES.index(name)]))


def step(n):
    return call("step", bytes([n - 1]))


def load(name, which, flips=(), cut=0, make_right=False):
    flipped = b"".join(struct.pack("<HB", at, xor) for at, xor in flips)
    return call(name, bytes([which, len(flips)]), flipped, struct.pack("<H", cut), bytes([1 if make_right else 0]))


def character(name, op, *args):  # name: CHARACTER_NAMES' index; op 0 add, 1 move, 2 remove, 3 get
    return call("character", bytes([name, op]), *args)


def get(body, floats=(0.0,) * 8, slot=0):
    return call("get", body, struct.pack("<8f", *floats), bytes([0, slot]))


def capi_seeds():
    zero3 = units(0) * 3
    start = bytes([8]) + find("ground") + find("box") + find("ball") + find("chassis")  # handles 0..3
    seeds = {
        "basic.bin": start + call("set_velocity", known(2), units(3), units(0), units(0), zero3) + step(8) +
        call("save", bytes([0])) + step(8) + load("load", 0) + get(known(2)) + step(4),
        "bounds.bin": start +
        call("set_velocity", known(2), edge(500), units(0), units(0), zero3) +
        call("set_velocity", known(2), edge(500, 1), units(0), units(0), zero3) +
        call("set_velocity", known(1), zero3, units(0), edge(100, -1, True), units(0)) +
        call("set_velocity", known(1), raw(2**63 - 1), raw(-2**63), raw(1), zero3) +
        call("set_velocity", known(2), double(float("nan")), double(float("inf")), double(1e300), zero3) +
        call("apply_impulse", known(2), edge(1000000), units(0), edge(1000000, 1, True), edge(16000), units(0), units(0)) +
        call("apply_force", known(1), units(0), edge(1000000, 1), units(0), zero3) +
        call("apply_force", known(1), units(10), units(0), units(0), edge(16000, 1), units(0), units(0)) +
        call("drive", bytes([0]), units(1), units(0), units(-1)) +
        call("drive", bytes([0]), edge(1, 1), units(0), units(0)) +
        call("drive", bytes([1]), units(1), units(0), units(0)) +
        call("cast_ray", units(0), units(5), units(0), units(0), units(-10), units(0)) +
        call("cast_ray", raw(2**63 - 1), raw(-2**63), units(0), raw(-2**63), raw(2**63 - 1), edge(131072, 1)) +
        step(8),
        "bodies.bin": start +
        call("add_body_fragment", fragment(0, ["0", "3", "0"])) +
        call("add_body_fragment", fragment(1, ["3", "0.5"])) +
        call("add_body_fragment", fragment(2, ["1", "0.5"])) +
        call("add_body_fragment", fragment(5, ["0", "90"])) +
        call("add_body_fragment", fragment(6, ["1"])) +
        call("add_joint_fragment", fragment(0, ["1", "3"])) +
        call("add_joint_fragment", fragment(1, ["1", "90"])) +
        call("add_joint_fragment", fragment(2, ["3"])) +
        step(8) + call("remove_body", known(4)) + call("remove_body", known(4)) +
        call("set_velocity", known(4), units(1), units(0), units(0), zero3) +
        call("remove_joint", bytes([0, 0])) + call("remove_joint", bytes([0, 0])) +
        call("remove_joint", bytes([0x80, 9, 3])) + call("remove_body", made_up(200, 1)) +
        call("add_body_fragment", fragment(0, ["0", "50", "0"])) + call("wake", known(2)) + step(8),
        "rollback.bin": start + step(2) +
        call("save_state", bytes([0])) + call("set_velocity", known(2), units(2), units(0), units(0), zero3) + step(6) +
        load("load_state", 0) + load("load_state", 0, flips=[(40, 1)]) +
        load("load_state", 0, flips=[(50, 0x10)], make_right=True) + load("load_state", 0, cut=9) +
        call("save", bytes([3])) + step(3) + load("load", 0, flips=[(30, 0xff)], make_right=True) +
        load("load", 0) + load("load_state", 0) + call("save_state", bytes([0])) + step(2) + load("load_state", 1),
        "malformed.bin": start +
        call("add_body_text", bytes([14]), b'{"shapes": [}]') +
        call("add_body_text", bytes([4]), b"\x00\xff{}") +
        call("add_body_fragment", fragment(0, ["nan", "inf", "1e300"])) +
        call("add_body_fragment", fragment(1, ["16000.000001", "0.009"])) +
        call("add_body_fragment", fragment(4, ["100001", "-100.5"])) +
        call("add_body_fragment", fragment(7, ["1e9"])) +
        call("add_body_fragment", fragment(3, ["-16001"], cut=20)) +
        call("add_joint_text", bytes([2]), b"[]") +
        call("add_joint_fragment", fragment(3, ["\"7\""])) + step(2),
        "nulls.bin": start + call("null_arguments", known(0)) + call("save", bytes([0])) +
        call("recreate", struct.pack("<H", 100), bytes([4])) + call("recreate", struct.pack("<H", 0), bytes([8])) +
        load("load", 0) + call("set_velocity", known(2), units(1), units(0), units(0), zero3) + step(2),
        # Characters join (one refused: a NaN position), walk, are read, leave.
        "characters.bin": start +
        character(0, 0, fragment(2, ["50", "1", "3"])) + character(1, 0, fragment(1, ["0.5", "1", "0.5"])) +
        character(0, 0, fragment(0, ["nan", "1", "0"])) +
        character(0, 1, units(1), units(0), units(0), bytes([1])) + step(8) + character(0, 3) +
        character(1, 2) + character(1, 3) + character(1, 2) + character(2, 1, units(1), units(0), units(0), bytes([0])) +
        character(0, 1, edge(100, 1), units(0), units(0), bytes([0])) + call("save", bytes([0])) + step(4) +
        load("load", 0) + character(0, 3),
        "getters.bin": start + step(4) +
        get(known(2), floats=(float("nan"), 1.0, float("inf"), 0.0, 0.0, 0.0, -0.0, float("nan")), slot=1) +
        get(made_up(50, 0), slot=7) + get(known(3), floats=(1e38, -1e38, 1e-45, 0.0, 1.0, 0.0, 0.0, 0.5)),
        # A ball from a struct thrown at 3 m/s, pinned by a struct joint that
        # breaks at 50 N s, the getters and events read as it flies and lands.
        "structs.bin": start + call("read_all", known(2), bytes([0, 8, 8, 8, 3, 1]), units(3), units(1), units(5)) +
        call("create_body_struct", bytes([2, 1]), units(0), units(3), units(2), bytes([0]), bytes([1]),
             units(3), units(0), units(0), bytes([0] * 8), bytes([2, 1, 3]), zero3, raw(2**31), units(0),
             bytes([0, 0xff])) +
        call("create_joint_struct", bytes([0]), known(0), known(4), units(0), units(3), units(2), bytes([0]),
             zero3, bytes([0, 0, 0, 1]), units(50), units(0), bytes([0])) +
        step(30) + call("read_all", known(4), bytes([0, 7, 2, 8, 1, 1]), units(-7), units(2), units(5)) +
        step(30) + call("read_all", known(4), bytes([1, 0, 0, 0, 0, 0]), raw(-2**63), units(1), raw(2**62)),
        "drive.bin": start + call("drive", bytes([0]), units(1), units(0), double(0.25)) + step(8) +
        call("save_state", bytes([0])) + step(8) + call("drive", bytes([0]), units(0), units(1), units(0)) +
        step(8) + load("load_state", 0) + step(8),
    }
    for name, data in seeds.items():
        write("capi", name, data)


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: python3 tools/fuzz/make_seeds.py BITSTEP")
    for name, text in scenes():
        write("scene", name, text)
    replays()
    settings()
    packets(snapshots(sys.argv[1]))
    capi_seeds()


main()
