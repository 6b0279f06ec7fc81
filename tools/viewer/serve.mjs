// Serves the viewer on 127.0.0.1 only, from the repository's own files:
//   /               tools/viewer/index.html (and /viewer/* its other files)
//   /engine/*       the wasm engine (build/wasm/tools/wasm/viewer, tools/build_wasm.sh)
//   /three/*        three.js, pinned in tools/viewer/package.json (tools/viewer/install.sh)
//   /scenes/*       the shipped scenes and golden replays
//   /files/*        the folder given with --files (a test's replays)
// Usage: node tools/viewer/serve.mjs [--port N (0: any free port; default 8080)]
//        [--files DIR] [--page QUERY] [--seconds S (stop after S seconds)]
// Prints "bitstep viewer: http://127.0.0.1:PORT/?QUERY" once it listens.
import { createServer } from 'node:http';
import { readFile } from 'node:fs/promises';
import { dirname, extname, join, resolve, sep } from 'node:path';
import { fileURLToPath } from 'node:url';

const root = resolve(dirname(fileURLToPath(import.meta.url)), '../..');
const options = { port: 8080, files: null, page: '', seconds: 0 };
const args = process.argv.slice(2);
for (let i = 0; i < args.length; ++i) {
  const value = args[i + 1];
  if (args[i] === '--port' && value !== undefined) options.port = Number(args[++i]);
  else if (args[i] === '--files' && value !== undefined) options.files = resolve(args[++i]);
  else if (args[i] === '--page' && value !== undefined) options.page = args[++i];
  else if (args[i] === '--seconds' && value !== undefined) options.seconds = Number(args[++i]);
  else {
    console.error(`serve.mjs: unknown or incomplete option '${args[i]}'`);
    process.exit(2);
  }
}
if (!Number.isInteger(options.port) || options.port < 0 || options.port > 65535) {
  console.error(`serve.mjs: --port: not a port number: ${options.port}`);
  process.exit(2);
}

const mounts = [
  ['/engine/', join(root, 'build/wasm/tools/wasm/viewer')],
  ['/three/', join(root, 'tools/viewer/node_modules/three')],
  ['/scenes/', join(root, 'scenes')],
  ['/viewer/', join(root, 'tools/viewer')],
];
if (options.files) mounts.push(['/files/', options.files]);

const types = {
  '.html': 'text/html; charset=utf-8', '.js': 'text/javascript', '.mjs': 'text/javascript',
  '.wasm': 'application/wasm', '.json': 'application/json', '.css': 'text/css', '.png': 'image/png',
};

// The file a URL path names, or null: only inside a mount (no "..").
function fileOf(path) {
  if (path === '/' || path === '/index.html') return join(root, 'tools/viewer/index.html');
  for (const [prefix, folder] of mounts) {
    if (!path.startsWith(prefix)) continue;
    const file = resolve(folder, '.' + decodeURIComponent(path.slice(prefix.length - 1)));
    return file.startsWith(folder + sep) ? file : null;
  }
  return null;
}

const server = createServer(async (request, response) => {
  const path = new URL(request.url, 'http://127.0.0.1').pathname;
  const file = fileOf(path);
  try {
    if (!file) throw new Error('outside the served folders');
    const body = await readFile(file);
    response.writeHead(200, { 'Content-Type': types[extname(file)] ?? 'application/octet-stream',
                              'Cache-Control': 'no-store' });
    response.end(body);
  } catch (error) {
    response.writeHead(404, { 'Content-Type': 'text/plain' });
    response.end(`${path}: not found\n`);
  }
});
server.on('error', (error) => {
  console.error(`serve.mjs: ${error.message}`);
  process.exit(1);
});
server.listen(options.port, '127.0.0.1', () => {
  const query = options.page ? `?${options.page}` : '';
  console.log(`bitstep viewer: http://127.0.0.1:${server.address().port}/${query}`);
});
if (options.seconds > 0) setTimeout(() => process.exit(0), options.seconds * 1000).unref();
