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
carrying a snapshot image.
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
                ("sliders_motors_30", "scenes/sliders_motors.json", 30)]
        for name, scene, step in runs:
            out = os.path.join(tmp, name + ".snapshot")
            subprocess.run([bitstep, "run", scene, "--steps", str(step + 1), "--snapshot-at", str(step), out],
                           check=True, stdout=subprocess.DEVNULL)
            images[name] = open(out, "rb").read()
            write("snapshot", name + ".snapshot", images[name])
    return images


def packet(kind, player, ack, tick, body):
    return b"bS" + bytes([1, kind, player]) + struct.pack("<qq", ack, tick) + body


def packets(images):
    inputs = [b"", b"\x01", b"left+jump", bytes(range(32))]
    write("packet", "inputs_0.bin", packet(0, 0, 0, 1, bytes([0])))
    write("packet", "inputs_1.bin", packet(0, 1, 5, 6, bytes([1]) + struct.pack("<H", 1) + b"\x01"))
    body = bytes([len(inputs)]) + b"".join(struct.pack("<H", len(i)) + i for i in inputs)
    write("packet", "inputs_4.bin", packet(0, 3, -1, 1 << 40, body))
    write("packet", "checksum.bin", packet(1, 2, 60, 60, struct.pack("<Q", 0xfbe30ec9ec0eefda)))
    state = images["small_1"]
    write("packet", "state.bin", packet(2, 1, 30, 30, struct.pack("<I", len(state)) + state))
    write("packet", "state_empty.bin", packet(2, 0, 0, 0, struct.pack("<I", 0)))
    for name, (player, players, mode, delay) in {"hello_rollback": (0, 2, 1, 2), "hello_lockstep": (3, 4, 0, 0)}.items():
        write("packet", name + ".bin", b"bS" + bytes([1, 16, player, players, mode, delay]) +
              struct.pack("<Q", 0x3c0e9c78ac0b4f0f))


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: python3 tools/fuzz/make_seeds.py BITSTEP")
    for name, text in scenes():
        write("scene", name, text)
    replays()
    settings()
    packets(snapshots(sys.argv[1]))


main()
