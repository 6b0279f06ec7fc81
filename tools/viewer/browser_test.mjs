// The viewer in a real browser: headless Chromium (Debian's, software
// WebGL) opens the page served on 127.0.0.1 (serve.mjs) in its test mode.
//   node tools/viewer/browser_test.mjs OUT_DIR   (engine_test.mjs wrote OUT_DIR's replays)
// 1. playground.replay.json played to step 120: the page reports a hash
//    for every step, each the golden one;
// 2. its screenshot (OUT_DIR/viewer.png) is not blank: at the page's
//    projected centres of bodies the pixels are not the background, at a
//    corner of the sky they are;
// 3. a tampered replay stops with "DIVERGED at step N" at its changed
//    input's step; beside the original it also names the first differing field;
// 4. the character course and the hills: their golden hashes in the page,
//    and in the course's screenshot each character drawn where it stands,
//    in its ground state's colour (its strongest channel).
import { spawn, spawnSync } from 'node:child_process';
import { readFileSync } from 'node:fs';
import { dirname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';
import { inflateSync } from 'node:zlib';

const root = resolve(dirname(fileURLToPath(import.meta.url)), '../..');
const out = resolve(process.argv[2] ?? join(root, 'build/viewer_test'));
let failures = 0;
function check(condition, what) {
  console.log(`${condition ? 'ok  ' : 'FAIL'} ${what}`);
  if (!condition) ++failures;
}

// The server, on a free port, stopped after 5 minutes whatever happens.
const server = spawn(process.execPath, [join(root, 'tools/viewer/serve.mjs'), '--port', '0', '--files', out,
                                        '--seconds', '300'], { stdio: ['ignore', 'pipe', 'inherit'] });
const base = await new Promise((resolveBase, reject) => {
  server.stdout.on('data', (data) => {
    const match = /http:\/\/127\.0\.0\.1:\d+\//.exec(String(data));
    if (match) resolveBase(match[0]);
  });
  server.on('exit', () => reject(new Error('serve.mjs exited')));
});

const chromiumFlags = ['--headless=new', '--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
                       '--hide-scrollbars', '--window-size=1000,700', '--virtual-time-budget=120000'];
function chromium(extra, query) {
  const run = spawnSync('chromium', [...chromiumFlags, ...extra, `${base}?${query}`],
                        { encoding: 'utf8', timeout: 180000, maxBuffer: 64 << 20 });
  if (run.error) throw run.error;
  return run.stdout;
}
// The page's report (#report) from its DOM.
function report(query) {
  const dom = chromium(['--dump-dom'], query);
  const match = /<pre id="report"[^>]*>([^<]*)<\/pre>/.exec(dom);
  if (!match) return { error: 'no report in the page' };
  return JSON.parse(match[1].replaceAll('&quot;', '"').replaceAll('&amp;', '&').replaceAll('&lt;', '<')
    .replaceAll('&gt;', '>'));
}

// A PNG's pixels (8-bit RGB or RGBA, not interlaced): (x, y) -> [r, g, b].
function readPng(file) {
  const data = readFileSync(file);
  let width = 0, height = 0, channels = 0;
  const idat = [];
  for (let at = 8; at < data.length;) {
    const length = data.readUInt32BE(at), type = data.toString('latin1', at + 4, at + 8);
    const body = data.subarray(at + 8, at + 8 + length);
    if (type === 'IHDR') {
      width = body.readUInt32BE(0);
      height = body.readUInt32BE(4);
      if (body[8] !== 8 || body[12] !== 0) throw new Error(`${file}: not an 8-bit, non-interlaced PNG`);
      channels = { 2: 3, 6: 4 }[body[9]];
      if (!channels) throw new Error(`${file}: colour type ${body[9]} is not RGB or RGBA`);
    } else if (type === 'IDAT') {
      idat.push(body);
    }
    at += 12 + length;
  }
  const raw = inflateSync(Buffer.concat(idat));
  const stride = width * channels;
  const pixels = Buffer.alloc(height * stride);
  for (let y = 0; y < height; ++y) {
    const filter = raw[y * (stride + 1)];
    const line = raw.subarray(y * (stride + 1) + 1, (y + 1) * (stride + 1));
    for (let i = 0; i < stride; ++i) {
      const a = i >= channels ? pixels[y * stride + i - channels] : 0;
      const b = y > 0 ? pixels[(y - 1) * stride + i] : 0;
      const c = i >= channels && y > 0 ? pixels[(y - 1) * stride + i - channels] : 0;
      const paeth = () => {
        const p = a + b - c, pa = Math.abs(p - a), pb = Math.abs(p - b), pc = Math.abs(p - c);
        return pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
      };
      const predictor = [0, a, b, (a + b) >> 1, paeth()][filter];
      pixels[y * stride + i] = (line[i] + predictor) & 0xff;
    }
  }
  return { width, height, at: (x, y) => [...pixels.subarray(y * stride + x * channels, y * stride + x * channels + 3)] };
}

try {
  const golden = JSON.parse(readFileSync(join(root, 'scenes/playground.replay.json'), 'utf8'));
  const to = 120;

  // 1. Every step's hash, in the page.
  const played = report(`replay=/scenes/playground.replay.json&to=${to}&test=1`);
  check(!played.error && !played.diverged, `the page played the replay (${played.error ?? played.diverged ?? 'no error'})`);
  const hashes = played.hashes ?? [];
  const same = hashes.filter((h, i) => h === golden.hashes[i]).length;
  check(played.tick === to && hashes.length === to && same === to,
        `the page reports ${hashes.length} step hashes to step ${played.tick}, ${same} of them the golden ones`);

  // 2. The screenshot.
  const shot = join(out, 'viewer.png');
  chromium([`--screenshot=${shot}`], `replay=/scenes/playground.replay.json&to=${to}&test=1`);
  const png = readPng(shot);
  const background = [0, 2, 4].map((k) => parseInt(played.background.slice(k, k + 2), 16));
  const distance = (p) => Math.abs(p[0] - background[0]) + Math.abs(p[1] - background[1]) + Math.abs(p[2] - background[2]);
  const probes = played.probes ?? [];
  const drawn = probes.filter((p) => distance(png.at(p.x, p.y)) > 40);
  check(png.width === 1000 && png.height === 700, `a ${png.width}x${png.height} screenshot`);
  check(probes.length >= 6 && drawn.length === probes.length,
        `${drawn.length} of ${probes.length} bodies' projected centres are drawn (not the background): ` +
        probes.map((p) => `${p.name} ${JSON.stringify(png.at(p.x, p.y))}`).join(', '));
  check(distance(png.at(played.sky.x, played.sky.y)) < 12, `the sky is the background ${JSON.stringify(png.at(played.sky.x, played.sky.y))}`);

  // 3. A tampered replay, alone and beside the original.
  const tampered = JSON.parse(readFileSync(join(out, 'tampered.replay.json'), 'utf8'));
  const changed = tampered.inputs.find((input) => input.type === 'impulse').step;
  const alone = report(`replay=/files/tampered.replay.json&to=${to}&test=1`);
  check(String(alone.diverged).startsWith(`DIVERGED at step ${changed}:`) && alone.tick === changed,
        `the tampered replay stops at step ${alone.tick}: ${alone.diverged}`);
  const beside = report(`replay=/files/tampered.replay.json&compare=/scenes/playground.replay.json&to=${to}&test=1`);
  check(/^DIVERGED at step \d+: .*\n\$\.\w+\[\d+\]/.test(String(beside.diverged)) && beside.tick === changed,
        `beside the original: ${JSON.stringify(beside.diverged)}`);
  // 4. The level's shapes and the characters.
  for (const name of ['course', 'hills']) {
    const recorded = JSON.parse(readFileSync(join(root, `scenes/${name}.replay.json`), 'utf8'));
    const query = `replay=/scenes/${name}.replay.json&to=${to}&test=1`;
    const page = report(query);
    const ok = (page.hashes ?? []).filter((h, i) => h === recorded.hashes[i]).length;
    check(!page.error && !page.diverged && ok === to, `${name}: ${ok} of ${to} step hashes the golden ones`);
    if (name !== 'course') continue;
    const courseShot = join(out, 'course.png');
    chromium([`--screenshot=${courseShot}`], query);
    const picture = readPng(courseShot);
    const strongest = (rgb) => rgb.indexOf(Math.max(...rgb));
    const seen = (page.characters ?? []).filter((c) => {
      const colour = [0, 2, 4].map((k) => parseInt(c.colour.slice(k, k + 2), 16));
      return strongest(picture.at(c.x, c.y)) === strongest(colour);
    });
    check(page.characters?.length === 2 && seen.length === 2,
          `course: ${seen.length} of ${page.characters?.length} characters drawn in their ground colour: ` +
          (page.characters ?? []).map((c) => `${c.name} #${c.colour} ${JSON.stringify(picture.at(c.x, c.y))}`).join(', '));
  }
} catch (error) {
  check(false, String(error.stack ?? error));
} finally {
  server.kill();
}
if (failures > 0) {
  console.error(`browser_test: ${failures} check(s) failed`);
  process.exit(1);
}
console.log('browser_test: every check passed');
