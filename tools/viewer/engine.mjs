// The wasm engine's C interface (tools/viewer/viewer_api.cpp) as a JS
// object, for the page (viewer.js) and for node (engine_test.mjs).
// `createBitstep` is the factory of build/wasm/tools/wasm/viewer/bitstep_viewer.js.

// "/a/b/../c.json" -> "/a/c.json"
export function normalize(path) {
  const parts = [];
  for (const part of path.split('/')) {
    if (part === '..') parts.pop();
    else if (part !== '.' && part !== '') parts.push(part);
  }
  return '/' + parts.join('/');
}

export async function openEngine(createBitstep, moduleOptions = {}) {
  const M = await createBitstep(moduleOptions);
  const fn = (name, result, args) => M.cwrap(name, result, args);
  const text7 = ['string', 'string', 'string', 'string', 'string', 'string', 'string'];
  const c = {
    error: fn('bv_error', 'string', []),
    loadReplay: fn('bv_load_replay', 'number', ['number', 'string']),
    loadScene: fn('bv_load_scene', 'number', ['number', 'string']),
    unload: fn('bv_unload', null, ['number']),
    loaded: fn('bv_loaded', 'number', ['number']),
    recordedSteps: fn('bv_recorded_steps', 'number', ['number']),
    tick: fn('bv_tick', 'number', ['number']),
    step: fn('bv_step', 'number', ['number']),
    divergedAt: fn('bv_diverged_at', 'number', ['number']),
    sceneMatches: fn('bv_scene_matches', 'number', ['number']),
    hash: fn('bv_hash', 'string', ['number']),
    recordedHash: fn('bv_recorded_hash', 'string', ['number', 'number']),
    seek: fn('bv_seek', 'number', ['number', 'number']),
    floatCount: fn('bv_float_count', 'number', ['number']),
    poses: fn('bv_poses', 'number', ['number']),
    contacts: fn('bv_contacts', 'number', ['number']),
    joints: fn('bv_joints', 'number', ['number']),
    characters: fn('bv_characters', 'number', ['number']),
    shapes: fn('bv_shapes', 'string', ['number']),
    click: fn('bv_click', 'number', ['number', ...text7]),
    replayJson: fn('bv_replay_json', 'string', ['number']),
    diff: fn('bv_diff', 'string', []),
  };
  // A copy of player v's last float buffer (the heap may move when it grows).
  const floats = (v, pointer) => {
    const n = c.floatCount(v);
    return pointer === 0 ? new Float32Array(0) : M.HEAPF32.slice(pointer / 4, pointer / 4 + n);
  };
  const check = (status) => {
    if (status !== 0) throw new Error(c.error());
  };
  return {
    module: M,
    // Files live in the module's memory file system.
    writeFile(path, text) {
      path = normalize(path);
      M.FS.mkdirTree(path.slice(0, path.lastIndexOf('/')) || '/');
      M.FS.writeFile(path, text);
      return path;
    },
    loadReplay: (v, path) => check(c.loadReplay(v, path)),
    loadScene: (v, path) => check(c.loadScene(v, path)),
    unload: (v) => c.unload(v),
    loaded: (v) => c.loaded(v) === 1,
    recordedSteps: (v) => c.recordedSteps(v),
    tick: (v) => c.tick(v),
    // 1: the recorded hash, 0: another, 2: no recorded hash for this step.
    step: (v) => c.step(v),
    divergedAt: (v) => c.divergedAt(v),
    sceneMatches: (v) => c.sceneMatches(v) === 1,
    hash: (v) => c.hash(v),
    recordedHash: (v, step) => c.recordedHash(v, step),
    seek: (v, tick) => c.seek(v, tick),
    poses: (v) => floats(v, c.poses(v)),
    contacts: (v) => floats(v, c.contacts(v)),
    joints: (v) => floats(v, c.joints(v)),
    characters: (v) => floats(v, c.characters(v)),
    shapes: (v) => JSON.parse(c.shapes(v)),
    // origin and direction: arrays of 3 numbers; the text sent is what the
    // recorded input holds (origin to 0.1 mm, direction to 1e-6).
    click(v, origin, direction, speed) {
      const o = origin.map((x) => x.toFixed(4));
      const d = direction.map((x) => x.toFixed(6));
      const slot = c.click(v, ...o, ...d, String(speed));
      if (slot === -2) throw new Error(c.error());
      return slot;
    },
    replayJson: (v) => c.replayJson(v),
    diff: () => c.diff(),
  };
}

// Writes a replay (its text, fetched or picked) and the scene it names into
// the engine's files under `folder`, and returns the replay's path there.
// `fetchScene(name)` gives the scene's text for the name the replay holds.
export async function stageReplay(engine, folder, fileName, text, fetchScene) {
  const path = engine.writeFile(`${folder}/${fileName}`, text);
  const scene = JSON.parse(text).scene;
  if (typeof scene === 'string') {
    engine.writeFile(`${folder}/${scene}`, await fetchScene(scene));
  }
  return path;
}
