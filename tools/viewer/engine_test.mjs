// The viewer's wasm engine under node, through the page's own wrapper
// (engine.mjs): what the browser test then shows on screen.
//   node --no-experimental-fetch tools/viewer/engine_test.mjs OUT_DIR
// 1. playground.replay.json re-simulated: every step's hash is the recorded one;
// 2. scrubbing back and forth (keyframe snapshots) lands on the recorded hashes;
// 3. a tampered copy (its first input's impulse changed, the chain kept)
//    diverges exactly at that input's step, and beside the original the
//    two states agree before it and differ at it, in a named field;
// 4. a click at step 60 pushes the body under the ray; the run to step 120
//    is written to OUT_DIR/clicked.replay.json (with its scene beside it)
//    for `bitstep verify` to accept natively (tools/viewer_test.sh), and
//    the tampered replay to OUT_DIR/tampered.replay.json for the browser;
// 5. the level's shapes and characters: hills.replay.json and
//    course.replay.json give their recorded chains; the heightfield and
//    the hulls come with the triangles or faces the page draws; the course's two characters come with their capsules and
//    ground states, and the one asked to walk moves.
import { copyFileSync, mkdirSync, readFileSync, writeFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { dirname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';
import { openEngine, stageReplay } from './engine.mjs';

const root = resolve(dirname(fileURLToPath(import.meta.url)), '../..');
const out = resolve(process.argv[2] ?? join(root, 'build/viewer_test'));
mkdirSync(out, { recursive: true });
const require = createRequire(import.meta.url);
const createBitstep = require(join(root, 'build/wasm/tools/wasm/viewer/bitstep_viewer.js'));
const engine = await openEngine(createBitstep);

let failures = 0;
function check(condition, what) {
  console.log(`${condition ? 'ok  ' : 'FAIL'} ${what}`);
  if (!condition) ++failures;
}

const scenes = join(root, 'scenes');
const goldenText = readFileSync(join(scenes, 'playground.replay.json'), 'utf8');
const golden = JSON.parse(goldenText);
const stage = (player, name, text) =>
  stageReplay(engine, `/data/${player}`, name, text, (scene) => readFileSync(join(scenes, scene), 'utf8'));

// 1. Every step as recorded.
engine.loadReplay(0, await stage(0, 'playground.replay.json', goldenText));
check(engine.sceneMatches(0), 'the scene hashes as recorded before step 1');
const steps = golden.steps;
let matched = 0;
const hashes = [];
for (let step = 1; step <= steps; ++step) {
  if (engine.step(0) === 1) ++matched;
  hashes.push(engine.hash(0));
}
check(matched === steps && hashes.every((h, i) => h === golden.hashes[i]),
      `playground: ${matched} of ${steps} steps give the recorded hash`);
check(engine.divergedAt(0) === 0, 'no divergence reported');

// 2. Scrubbing.
for (const tick of [45, 7, 0, 119, 60, 120]) {
  engine.seek(0, tick);
  const expected = tick === 0 ? golden.scene_hash : golden.hashes[tick - 1];
  check(engine.tick(0) === tick && engine.hash(0) === expected, `seek to step ${tick}: hash ${engine.hash(0)}`);
}

// 3. A tampered copy.
const tampered = JSON.parse(goldenText);
const first = tampered.inputs.find((input) => input.type === 'impulse');
first.impulse[0] += 1;
const tamperedText = JSON.stringify(tampered, null, 1);
writeFileSync(join(out, 'tampered.replay.json'), tamperedText);
copyFileSync(join(scenes, golden.scene), join(out, golden.scene));
engine.loadReplay(0, await stage(0, 'tampered.replay.json', tamperedText));
engine.loadReplay(1, await stage(1, 'playground.replay.json', goldenText));
let firstDifference = 0;
for (let step = 1; step <= steps; ++step) {
  engine.step(0);
  engine.step(1);
  if (firstDifference === 0 && engine.hash(0) !== engine.hash(1)) firstDifference = step;
}
check(engine.divergedAt(0) === first.step, `tampered: diverges at step ${engine.divergedAt(0)} (its input's: ${first.step})`);
engine.seek(0, first.step - 1);
engine.seek(1, first.step - 1);
check(engine.diff() === '', `beside the original, the states agree at step ${first.step - 1}`);
engine.seek(0, first.step);
engine.seek(1, first.step);
const diff = engine.diff();
check(firstDifference === first.step && /^\$\.\w+\[\d+\]/.test(diff),
      `and first differ at step ${first.step}: ${diff}`);
engine.unload(1);

// 4. A click at step 60, recorded.
engine.loadReplay(0, await stage(0, 'playground.replay.json', goldenText));
engine.seek(0, 60);
const poses = engine.poses(0);
const shapes = engine.shapes(0);
// The first dynamic body awake: the ray comes down onto its centre from 20 m up.
const target = shapes.find((b) => b.type === 'dynamic' && (poses[b.slot * 9] & 2) === 0);
const at = [poses[target.slot * 9 + 2], poses[target.slot * 9 + 3], poses[target.slot * 9 + 4]];
const pushed = engine.click(0, [at[0], at[1] + 20, at[2]], [0, -1, 0], 3);
check(pushed >= 0, `a click from above ${target.name} pushes slot ${pushed}`);
check(engine.recordedSteps(0) === 60, 'the recorded chain now ends at the click');
let live = 0;
while (engine.tick(0) < steps) live += engine.step(0) === 2 ? 1 : 0;
check(live === steps - 60, `steps 61-${steps} run live (${live})`);
check(engine.hash(0) !== golden.hashes[steps - 1], 'the push changed the run');
const clicked = engine.replayJson(0);
writeFileSync(join(out, 'clicked.replay.json'), clicked);
const clickedReplay = JSON.parse(clicked);
check(clickedReplay.steps === steps && clickedReplay.hashes.length === steps &&
      clickedReplay.hashes.slice(0, 60).every((h, i) => h === golden.hashes[i]) &&
      clickedReplay.inputs.at(-1).step === 61 && clickedReplay.inputs.at(-1).body === pushed,
      `clicked.replay.json: ${steps} steps, the golden chain to step 60, the push at step 61`);

// 5. Hulls, meshes, heightfields and characters.
for (const name of ['hills', 'course']) {
  const text = readFileSync(join(scenes, `${name}.replay.json`), 'utf8');
  const recorded = JSON.parse(text);
  engine.loadReplay(0, await stage(0, `${name}.replay.json`, text));
  let same = 0;
  for (let step = 1; step <= 120; ++step) same += engine.step(0) === 1 ? 1 : 0;
  check(same === 120 && engine.hash(0) === recorded.hashes[119], `${name}: 120 of 120 steps as recorded`);
  const drawn = engine.shapes(0).flatMap((b) => b.shapes);
  const withFaces = (type) => drawn.filter((s) => s.type === type && s.faces && s.faces.length > 0 && s.vertices);
  if (name === 'hills') {
    const field = withFaces('heightfield');
    check(field.length === 1 && field[0].faces.length >= 4000,
          `hills: the heightfield comes as ${field[0]?.faces.length} triangles to draw`);
    check(withFaces('hull').length > 0, `hills: ${withFaces('hull').length} hulls come with their faces`);
  } else {
    const c = engine.characters(0);
    const alive = [];
    for (let i = 0; i < c.length; i += 9) if (c[i] === 1) alive.push(c.subarray(i, i + 9));
    check(alive.length === 2 && alive.every((k) => k[5] > 0 && k[6] > 0 && k[1] >= 0 && k[1] <= 2),
          `course: ${alive.length} characters with their capsules and ground states`);
    const before = alive.map((k) => [k[2], k[4]]);
    for (let step = 0; step < 60; ++step) engine.step(0);
    const after = engine.characters(0);
    const moved = before.some(([x, z], k) => Math.hypot(after[k * 9 + 2] - x, after[k * 9 + 4] - z) > 0.5);
    check(moved, 'course: a character walks over 0.5 m in the next second');
  }
}
engine.unload(0);

if (failures > 0) {
  console.error(`engine_test: ${failures} check(s) failed`);
  process.exit(1);
}
console.log('engine_test: every check passed');
