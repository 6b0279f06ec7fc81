// bitstep's replay viewer: the wasm engine re-simulates a replay and checks
// each step's state hash against the recorded chain while three.js draws it.
//
// URL parameters: replay=URL | scene=URL (a scene played live), compare=URL
// (a second replay stepped beside the first: the first step where the two
// states differ stops both, with the first differing field), to=N (play to
// step N, then pause), play=1, follow=NAME, contacts=0|1, camera=EYE,TARGET
// (six numbers), test=1 (tools/viewer_test.sh:
// play to `to` as fast as possible, then write a JSON report into #report).
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { openEngine, stageReplay } from '/viewer/engine.mjs';

const $ = (id) => document.getElementById(id);
const params = new URLSearchParams(location.search);
const testing = params.get('test') === '1';

const engine = await openEngine(window.createBitstep, { locateFile: (file) => `/engine/${file}` });

// --- the scene graph ----------------------------------------------------------
const canvas = $('view');
if (testing) {
  // One size whatever the window (the test's report and its screenshot
  // come from two runs of the page, and must project alike).
  canvas.style.width = '960px';
  canvas.style.height = '600px';
}
const renderer = new THREE.WebGLRenderer({ canvas, antialias: !testing, preserveDrawingBuffer: true });
renderer.setPixelRatio(testing ? 1 : window.devicePixelRatio);
const background = new THREE.Color(0x1d232b);
const scene = new THREE.Scene();
scene.background = background;
scene.add(new THREE.HemisphereLight(0xffffff, 0x404850, 1.6));
const sun = new THREE.DirectionalLight(0xffffff, 1.6);
sun.position.set(30, 60, 20);
scene.add(sun);
const camera = new THREE.PerspectiveCamera(50, 1, 0.05, 2000);
const controls = new OrbitControls(camera, canvas);

// Body colours: dynamic bodies by slot (a fixed hue walk), asleep ones in
// slate, static ones grey, kinematic ones orange. Comparing, the second
// player's world is drawn beside the first's (the right half, one camera).
const sleepingColour = new THREE.Color(0x56657a);
const staticColour = new THREE.Color(0x7d8590);
const kinematicColour = new THREE.Color(0xd98c3a);

// A hull's faces as flat-shaded triangles: each loop (counter-clockwise
// seen from outside) fanned from its first corner.
function hullGeometry(vertices, faces) {
  const positions = [];
  for (const loop of faces) {
    for (let i = 1; i + 1 < loop.length; ++i) {
      for (const k of [loop[0], loop[i], loop[i + 1]])
        positions.push(vertices[3 * k], vertices[3 * k + 1], vertices[3 * k + 2]);
    }
  }
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.Float32BufferAttribute(positions, 3));
  geometry.computeVertexNormals();
  return geometry;
}

// A character on the ground, on a steep slope, in the air.
const groundColours = [new THREE.Color(0x40c060), new THREE.Color(0xe09030), new THREE.Color(0x4080e0)];
const awakeColour = (slot) => new THREE.Color().setHSL(((slot * 0.618034) % 1 + 1) % 1, 0.55, 0.55);

class Drawing {
  constructor(player) {
    this.player = player;
    this.root = new THREE.Group();
    scene.add(this.root);
    this.bodies = []; // per slot: {generation, group, materials, slot, name}
    this.contactPoints = new THREE.Points(new THREE.BufferGeometry(),
      new THREE.PointsMaterial({ color: 0xff3030, size: 3, sizeAttenuation: false }));
    this.contactNormals = new THREE.LineSegments(new THREE.BufferGeometry(),
      new THREE.LineBasicMaterial({ color: 0xff8080 }));
    this.jointLines = new THREE.LineSegments(new THREE.BufferGeometry(),
      new THREE.LineBasicMaterial({ color: 0xffe070, depthTest: false }));
    this.characters = []; // per character slot: {group, material}
    for (const o of [this.contactPoints, this.contactNormals, this.jointLines]) {
      o.renderOrder = 10;
      o.frustumCulled = false;
      this.root.add(o);
    }
  }

  clear() {
    for (const b of this.bodies) if (b) this.root.remove(b.group);
    for (const c of this.characters) this.root.remove(c.group);
    this.bodies = [];
    this.characters = [];
  }

  // The characters: an upright capsule each, coloured by its ground state
  // (on ground, on a steep slope, in the air), a nose where it faces.
  updateCharacters() {
    const c = engine.characters(this.player);
    const count = c.length / 9;
    while (this.characters.length < count) {
      const i = this.characters.length * 9;
      const material = new THREE.MeshLambertMaterial();
      const group = new THREE.Group();
      group.add(new THREE.Mesh(new THREE.CapsuleGeometry(c[i + 5], 2 * c[i + 6], 6, 16), material));
      const nose = new THREE.Mesh(new THREE.BoxGeometry(0.1, 0.1, 0.5 * c[i + 5]), material);
      nose.position.set(0, 0.5 * c[i + 6], c[i + 5]);
      group.add(nose);
      this.root.add(group);
      this.characters.push({ group, material });
    }
    for (let k = 0; k < this.characters.length; ++k) {
      const i = k * 9, drawn = this.characters[k];
      drawn.group.visible = k < count && c[i] === 1;
      if (!drawn.group.visible) continue;
      drawn.group.position.set(c[i + 2], c[i + 3], c[i + 4]);
      drawn.group.rotation.set(0, Math.atan2(c[i + 7], c[i + 8]), 0);
      drawn.material.color.copy(groundColours[c[i + 1]] || groundColours[2]);
    }
  }

  meshOf(shape, material) {
    let geometry;
    if (shape.type === 'box') {
      const [x, y, z] = shape.half_extents;
      geometry = new THREE.BoxGeometry(2 * x, 2 * y, 2 * z);
    } else if (shape.type === 'sphere') {
      geometry = new THREE.SphereGeometry(shape.radius[0], 24, 16);
    } else if (shape.type === 'capsule') {
      geometry = new THREE.CapsuleGeometry(shape.radius[0], 2 * shape.half_height[0], 6, 16);
    } else if (shape.faces) { // a hull, a mesh or a heightfield's triangles
      geometry = hullGeometry(shape.vertices, shape.faces);
    } else {
      geometry = new THREE.PlaneGeometry(400, 400).rotateX(-Math.PI / 2); // the plane's normal is its local +y
    }
    const mesh = new THREE.Mesh(geometry, material);
    mesh.position.fromArray(shape.position);
    mesh.quaternion.fromArray(shape.orientation);
    return mesh;
  }

  // Rebuilds the meshes of slots whose body was created or removed.
  sync(poses) {
    const count = poses.length / 9;
    let stale = this.bodies.length !== count;
    for (let slot = 0; slot < count && !stale; ++slot) {
      const alive = (poses[slot * 9] & 1) === 1;
      const body = this.bodies[slot];
      stale = alive !== Boolean(body) || (alive && body.generation !== poses[slot * 9 + 1]);
    }
    if (!stale) return;
    this.clear();
    this.bodies = new Array(count).fill(null);
    for (const b of engine.shapes(this.player)) {
      const group = new THREE.Group();
      const material = new THREE.MeshLambertMaterial();
      if (b.type === 'static') material.color.copy(staticColour);
      for (const shape of b.shapes) group.add(this.meshOf(shape, material));
      group.matrixAutoUpdate = true;
      this.root.add(group);
      this.bodies[b.slot] = { generation: b.generation, group, material, slot: b.slot, name: b.name, type: b.type };
    }
  }

  update(showContacts, showJoints) {
    const poses = engine.poses(this.player);
    this.sync(poses);
    for (const body of this.bodies) {
      if (!body) continue;
      const i = body.slot * 9;
      const flags = poses[i];
      body.group.position.set(poses[i + 2], poses[i + 3], poses[i + 4]);
      body.group.quaternion.set(poses[i + 5], poses[i + 6], poses[i + 7], poses[i + 8]);
      body.flags = flags;
      if (flags & 4) body.material.color.copy(flags & 2 ? sleepingColour : awakeColour(body.slot));
      else if (flags & 8) body.material.color.copy(kinematicColour);
    }
    this.updateCharacters();
    const contacts = showContacts ? engine.contacts(this.player) : new Float32Array(0);
    const points = [], normals = [];
    for (let i = 0; i < contacts.length; i += 6) {
      const [x, y, z, nx, ny, nz] = contacts.subarray(i, i + 6);
      points.push(x, y, z);
      normals.push(x, y, z, x + 0.15 * nx, y + 0.15 * ny, z + 0.15 * nz);
    }
    this.contactPoints.geometry.setAttribute('position', new THREE.Float32BufferAttribute(points, 3));
    this.contactNormals.geometry.setAttribute('position', new THREE.Float32BufferAttribute(normals, 3));
    const joints = showJoints ? engine.joints(this.player) : new Float32Array(0);
    this.jointLines.geometry.setAttribute('position', new THREE.Float32BufferAttribute(Array.from(joints), 3));
  }
}

const drawings = [new Drawing(0), new Drawing(1)];

// --- the players ---------------------------------------------------------------
const state = {
  playing: false,
  diverged: null,     // the message shown once a step's hash differs
  comparing: false,
  recordedSteps: 0,
  clock: 0,
  hashes: [],         // test mode: the page's hash after each step
  clicked: false,
};

function showDiverged(message) {
  state.diverged = message;
  state.playing = false;
  $('diverged').hidden = false;
  $('diverged').textContent = message;
  $('play').textContent = '▶';
}

// One step of every loaded player; false once a step diverges.
function stepAll() {
  const result = engine.step(0);
  if (state.comparing) engine.step(1);
  const tick = engine.tick(0);
  if (testing) state.hashes.push(engine.hash(0));
  if (result === 0) {
    showDiverged(`DIVERGED at step ${tick}: recorded ${engine.recordedHash(0, tick)}, computed ${engine.hash(0)}` +
                 (state.comparing ? `\n${engine.diff() || 'the two replays agree at this step'}` : ''));
    return false;
  }
  if (state.comparing && engine.hash(0) !== engine.hash(1)) {
    showDiverged(`DIVERGED at step ${tick}: the two replays' states differ\n${engine.diff()}`);
    return false;
  }
  return true;
}

function refresh() {
  const tick = engine.tick(0);
  const recorded = engine.recordedHash(0, tick);
  $('step-label').textContent = `step ${tick} / ${state.recordedSteps || 'live'}`;
  const label = $('hash-label');
  if (tick === 0) {
    label.textContent = engine.sceneMatches(0) ? '' : 'the scene differs from the recorded one';
    label.className = '';
  } else if (recorded) {
    const ok = recorded === engine.hash(0);
    label.textContent = `hash ${engine.hash(0)} ${ok ? '✓ as recorded' : '✗ recorded ' + recorded}`;
    label.className = ok ? 'ok' : '';
  } else {
    label.textContent = `hash ${engine.hash(0)} (live: recording)`;
    label.className = 'live';
  }
  const scrub = $('scrub');
  scrub.max = Math.max(state.recordedSteps, tick, Number(scrub.max));
  scrub.value = tick;
  drawings[0].update($('show-contacts').checked, $('show-joints').checked);
  if (state.comparing) drawings[1].update($('show-contacts').checked, $('show-joints').checked);
  follow();
}

function follow() {
  const name = $('follow').value;
  const body = drawings[0].bodies.find((b) => b && b.name === name);
  if (!body) return;
  const delta = body.group.position.clone().sub(controls.target);
  controls.target.add(delta);
  camera.position.add(delta);
}

// Frames the dynamic bodies: the camera looks at their middle from a
// distance that fits them.
function frame() {
  const box = new THREE.Box3();
  for (const b of drawings[0].bodies) if (b && b.type !== 'static') box.expandByObject(b.group);
  if (box.isEmpty()) for (const b of drawings[0].bodies) if (b) box.expandByObject(b.group);
  const centre = box.getCenter(new THREE.Vector3());
  const size = Math.min(Math.max(box.getSize(new THREE.Vector3()).length(), 2), 400);
  controls.target.copy(centre);
  camera.position.copy(centre).add(new THREE.Vector3(0.55, 0.45, 0.7).multiplyScalar(size * 0.9));
  camera.near = size / 1000;
  camera.far = size * 20;
  // camera=EYE_X,EYE_Y,EYE_Z,TARGET_X,TARGET_Y,TARGET_Z (m) in the URL instead.
  const view = (params.get('camera') ?? '').split(',').map(Number);
  if (view.length === 6 && view.every(Number.isFinite)) {
    camera.position.fromArray(view, 0);
    controls.target.fromArray(view, 3);
  }
  camera.updateProjectionMatrix();
  controls.update();
}

function fillFollow() {
  const select = $('follow');
  select.length = 1;
  for (const b of drawings[0].bodies) {
    if (b && b.type === 'dynamic') select.add(new Option(b.name, b.name));
  }
  if (params.get('follow')) select.value = params.get('follow');
}

function afterLoad() {
  state.recordedSteps = engine.recordedSteps(0);
  state.diverged = null;
  $('diverged').hidden = true;
  $('scrub').max = state.recordedSteps;
  $('download').disabled = false;
  drawings[0].clear();
  drawings[1].clear();
  drawings[0].sync(engine.poses(0));
  if (state.comparing) drawings[1].sync(engine.poses(1));
  // Contact points crowd a large scene: shown by default below 400 bodies
  // (contacts=0 or 1 in the URL decides).
  const bodies = drawings[0].bodies.filter(Boolean).length;
  $('show-contacts').checked = params.has('contacts') ? params.get('contacts') === '1' : bodies < 400;
  fillFollow();
  refresh();  // poses the bodies, which frame() then fits in view
  frame();
}

async function fetchText(url) {
  const response = await fetch(url);
  if (!response.ok) throw new Error(`${url}: HTTP ${response.status}`);
  return response.text();
}

async function loadUrl(player, url, asScene) {
  const base = new URL(url, location.href);
  const fileName = base.pathname.slice(base.pathname.lastIndexOf('/') + 1);
  const folder = `/data/player${player}/url`;
  if (asScene) {
    engine.loadScene(player, engine.writeFile(`${folder}/${fileName}`, await fetchText(base)));
  } else {
    const path = await stageReplay(engine, folder, fileName, await fetchText(base),
                                   (scene) => fetchText(new URL(scene, base)));
    engine.loadReplay(player, path);
  }
}

// Picked files: the replay (a file with "hashes") and the scene it names,
// picked together; or a scene alone.
async function loadPicked(player, files) {
  const folder = `/data/player${player}/picked`;
  const texts = {};
  for (const file of files) texts[file.name] = await file.text();
  const replayName = Object.keys(texts).find((name) => 'hashes' in JSON.parse(texts[name]));
  if (!replayName) {
    const name = Object.keys(texts)[0];
    engine.loadScene(player, engine.writeFile(`${folder}/${name}`, texts[name]));
    return;
  }
  // The scene is the picked file of the same name, whatever folder the
  // replay names it in.
  const path = await stageReplay(engine, folder, replayName, texts[replayName], (scene) => {
    const base = scene.slice(scene.lastIndexOf('/') + 1);
    if (!(base in texts)) throw new Error(`${replayName} names the scene ${scene}: pick it too`);
    return texts[base];
  });
  engine.loadReplay(player, path);
}

function fail(error) {
  showDiverged(String(error.message ?? error));
  $('diverged').style.background = '#5a4a1b';
  if (testing) report({ error: String(error.message ?? error) });
}

// --- controls --------------------------------------------------------------------
$('play').onclick = () => {
  state.playing = !state.playing && !state.diverged;
  $('play').textContent = state.playing ? '❚❚' : '▶';
};
$('step').onclick = () => { if (!state.diverged) { stepAll(); refresh(); } };
$('scrub').oninput = () => {
  const tick = Number($('scrub').value);
  state.diverged = null;
  $('diverged').hidden = true;
  engine.seek(0, tick);
  if (state.comparing) engine.seek(1, tick);
  refresh();
};
$('open').onchange = async (event) => {
  try {
    state.comparing = false;
    engine.unload(1);
    await loadPicked(0, [...event.target.files]);
    afterLoad();
  } catch (error) { fail(error); }
};
$('compare').onchange = async (event) => {
  try {
    await loadPicked(1, [...event.target.files]);
    state.comparing = true;
    engine.seek(1, engine.tick(0));
    afterLoad();
  } catch (error) { fail(error); }
};
$('download').onclick = () => {
  const blob = new Blob([engine.replayJson(0)], { type: 'application/json' });
  const link = document.createElement('a');
  link.href = URL.createObjectURL(blob);
  link.download = `viewer-step${engine.tick(0)}.replay.json`;
  link.click();
};
document.addEventListener('keydown', (event) => {
  if (event.key === ' ') $('play').click();
  if (event.key === '.') $('step').click();
});

// A click that did not drag: the ray through the pixel pushes the body it
// meets at 3 m/s (the impulse is its mass times that), as an input of the
// next step. From here on the run is a new recording.
let pressed = null;
canvas.addEventListener('pointerdown', (event) => { pressed = [event.clientX, event.clientY]; });
canvas.addEventListener('pointerup', (event) => {
  if (!pressed || Math.hypot(event.clientX - pressed[0], event.clientY - pressed[1]) > 4) return;
  const rect = canvas.getBoundingClientRect();
  // Comparing, the left half is the first player's view, the one clicks push.
  const width = state.comparing ? rect.width / 2 : rect.width;
  if (event.clientX - rect.left > width) return;
  const pointer = new THREE.Vector2(((event.clientX - rect.left) / width) * 2 - 1,
                                    -((event.clientY - rect.top) / rect.height) * 2 + 1);
  const ray = new THREE.Raycaster();
  ray.setFromCamera(pointer, camera);
  const slot = engine.click(0, ray.ray.origin.toArray(), ray.ray.direction.toArray(), 3);
  if (slot >= 0) {
    state.recordedSteps = 0;
    state.diverged = null;
    $('diverged').hidden = true;
    $('hash-label').textContent = `pushed ${drawings[0].bodies[slot]?.name ?? slot} at step ${engine.tick(0) + 1}`;
  }
});

function resize() {
  const width = canvas.clientWidth, height = canvas.clientHeight;
  if (canvas.width !== width || canvas.height !== height) renderer.setSize(width, height, false);
  const aspect = (state.comparing ? width / 2 : width) / height;
  if (camera.aspect !== aspect) {
    camera.aspect = aspect;
    camera.updateProjectionMatrix();
  }
}

// One world, or the two side by side (the first on the left).
function render() {
  const width = canvas.clientWidth, height = canvas.clientHeight;
  drawings[1].root.visible = false;
  if (!state.comparing) {
    renderer.setScissorTest(false);
    renderer.setViewport(0, 0, width, height);
    renderer.render(scene, camera);
    return;
  }
  renderer.setScissorTest(true);
  for (const side of [0, 1]) {
    drawings[0].root.visible = side === 0;
    drawings[1].root.visible = side === 1;
    renderer.setViewport(side * width / 2, 0, width / 2, height);
    renderer.setScissor(side * width / 2, 0, width / 2, height);
    renderer.render(scene, camera);
  }
  drawings[0].root.visible = true;
}

function loop(time) {
  resize();
  if (state.playing) {
    const speed = Number($('speed').value);
    state.clock += Math.min((time - (state.last ?? time)) / 1000, 0.1) * speed;
    let steps = 0;
    while (state.clock >= 1 / 60 && steps < 8) {
      state.clock -= 1 / 60;
      ++steps;
      if (!stepAll()) break;
      const to = Number(params.get('to') ?? 0);
      if (to > 0 && engine.tick(0) >= to) {
        state.playing = false;
        $('play').textContent = '▶';
        break;
      }
    }
    refresh();
  }
  state.last = time;
  controls.update();
  render();
  requestAnimationFrame(loop);
}

// --- test mode: play to `to` at once, draw, report -----------------------------------
function report(fields) {
  $('report').textContent = JSON.stringify(fields);  // read from the DOM, not drawn
  document.title = 'bitstep viewer: done';
}

async function runTest() {
  const to = Number(params.get('to') ?? 120);
  while (engine.tick(0) < to && !state.diverged) {
    for (let k = 0; k < 20 && engine.tick(0) < to; ++k) if (!stepAll()) break;
    await new Promise((resolve) => setTimeout(resolve, 0));
  }
  refresh();
  resize();
  controls.update();
  render();
  // Probes: where some bodies' centres fall on the page, and a corner of
  // the sky, for the test to read from the screenshot.
  const rect = canvas.getBoundingClientRect();
  const probes = [];
  for (const b of drawings[0].bodies) {
    if (!b || b.type !== 'dynamic' || probes.length >= 12) continue;
    const p = b.group.position.clone().project(camera);
    const x = Math.round(rect.left + (p.x + 1) / 2 * rect.width);
    const y = Math.round(rect.top + (1 - p.y) / 2 * rect.height);
    if (p.z < 1 && x > rect.left + 2 && x < rect.right - 2 && y > rect.top + 40 && y < rect.bottom - 30) {
      probes.push({ name: b.name, x, y });
    }
  }
  // And the characters' centres, with their ground state (its colour).
  const characters = [];
  drawings[0].characters.forEach((c, k) => {
    if (!c.group.visible) return;
    const p = c.group.position.clone().project(camera);
    const x = Math.round(rect.left + (p.x + 1) / 2 * rect.width);
    const y = Math.round(rect.top + (1 - p.y) / 2 * rect.height);
    if (p.z < 1 && x > rect.left + 2 && x < rect.right - 2 && y > rect.top + 40 && y < rect.bottom - 30) {
      characters.push({ name: `character ${k}`, x, y, colour: c.material.color.getHexString() });
    }
  });
  report({
    tick: engine.tick(0),
    characters,
    recorded_steps: state.recordedSteps,
    hashes: state.hashes,
    diverged: state.diverged,
    probes,
    sky: { x: Math.round(rect.right - 20), y: Math.round(rect.top + 20) },
    background: background.getHexString(),
  });
}

try {
  if (params.get('replay')) await loadUrl(0, params.get('replay'), false);
  else if (params.get('scene')) await loadUrl(0, params.get('scene'), true);
  if (params.get('compare')) {
    await loadUrl(1, params.get('compare'), false);
    state.comparing = true;
  }
  if (engine.loaded(0)) afterLoad();
  if (testing) await runTest();
  else state.playing = params.get('play') === '1';
} catch (error) {
  fail(error);
}
requestAnimationFrame(loop);
