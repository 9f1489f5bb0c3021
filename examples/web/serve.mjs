// Local server of the three.js example (examples/web/README.md): serves
// this folder, three.js from node_modules, the repository's data/ and the
// single-file shader library the build writes (<build>/shaders/flat).
//
//   node examples/web/serve.mjs [--shaders DIR] [--port N]
//
// DIR defaults to build/shaders/flat of the repository (scripts/run builds
// it), or share/surfgrad/shaders/flat in an installation. A request is
// answered only from inside those folders (no path leaves them).
import { createServer } from 'node:http';
import { readFile, stat } from 'node:fs/promises';
import { dirname, extname, join, normalize, resolve, sep } from 'node:path';
import { fileURLToPath } from 'node:url';

const here = dirname(fileURLToPath(import.meta.url));
const repo = resolve(here, '..', '..');

const types = {
  '.html': 'text/html; charset=utf-8', '.js': 'text/javascript', '.mjs': 'text/javascript',
  '.json': 'application/json', '.gltf': 'model/gltf+json', '.bin': 'application/octet-stream',
  '.png': 'image/png', '.jpg': 'image/jpeg', '.glsl': 'text/plain; charset=utf-8',
};

// The file under `root` that `rest` names, or null when it would leave root.
function inside(root, rest) {
  const path = normalize(join(root, decodeURIComponent(rest)));
  return path === root || path.startsWith(root + sep) ? path : null;
}

// The single-file library: the build's (a source tree built into build/),
// else the installation's (share/surfgrad/shaders/flat beside the examples).
async function defaultShaders() {
  for (const dir of [join(repo, 'build', 'shaders', 'flat'), join(repo, 'shaders', 'flat')]) {
    try {
      if ((await stat(join(dir, 'surfgrad.glsl'))).isFile()) return dir;
    } catch {}
  }
  return join(repo, 'build', 'shaders', 'flat');
}

// Starts the server; resolves to { url, close() }. port 0: any free port.
export async function startServer({ shadersDir, port = 0 } = {}) {
  shadersDir ??= await defaultShaders();
  const mounts = [
    ['/node_modules/', join(here, 'node_modules')],
    ['/data/', join(repo, 'data')],
    ['/shaders/', resolve(shadersDir)],
    ['/', here],
  ];
  const server = createServer(async (req, res) => {
    const url = new URL(req.url, 'http://localhost');
    let path = url.pathname === '/' ? '/index.html' : url.pathname;
    for (const [prefix, root] of mounts) {
      if (!path.startsWith(prefix)) continue;
      const file = inside(root, path.slice(prefix.length));
      try {
        if (!file || !(await stat(file)).isFile()) throw new Error('not a file');
        res.writeHead(200, { 'Content-Type': types[extname(file)] ?? 'application/octet-stream' });
        res.end(await readFile(file));
      } catch {
        res.writeHead(404, { 'Content-Type': 'text/plain' });
        res.end(`not found: ${path}\n`);
      }
      return;
    }
  });
  await new Promise((ok, fail) => server.listen(port, '127.0.0.1', ok).on('error', fail));
  return { url: `http://127.0.0.1:${server.address().port}/`, close: () => server.close() };
}

if (process.argv[1] === fileURLToPath(import.meta.url)) {
  const args = process.argv.slice(2);
  const opt = (name) => { const i = args.indexOf(name); return i >= 0 ? args[i + 1] : undefined; };
  const shadersDir = opt('--shaders');
  if (shadersDir !== undefined) {
    try {
      if (!(await stat(join(shadersDir, 'surfgrad.glsl'))).isFile()) throw new Error();
    } catch {
      console.error(`serve.mjs: ${join(shadersDir, 'surfgrad.glsl')} not found (build the project first)`);
      process.exit(2);
    }
  }
  const { url } = await startServer({ shadersDir, port: Number(opt('--port') ?? 8080) });
  console.log(`surfgrad three.js example: open ${url}`);
}
