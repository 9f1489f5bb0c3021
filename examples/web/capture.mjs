// Loads the three.js example in headless Chromium (WebGL2 on SwiftShader)
// through the DevTools protocol and writes what the canvas shows: the
// browser test of tests/web (docs/engines.md, "three.js").
//
//   node capture.mjs --chromium PATH --shaders DIR --query QUERY --out FILE [--png FILE]
//
// QUERY is the page's URL parameters (main.js). FILE receives the canvas as
// raw RGBA8 rows, top row first, after an 8-byte header (width, height as
// little-endian uint32). Exits 1 naming the message when the page logs a
// console error, throws, or a request fails; 2 on bad arguments.
import { writeFile, rename } from 'node:fs/promises';
import puppeteer from 'puppeteer-core';
import { startServer } from './serve.mjs';

const args = process.argv.slice(2);
const opt = (name) => { const i = args.indexOf(name); return i >= 0 ? args[i + 1] : undefined; };
const chromium = opt('--chromium'), shadersDir = opt('--shaders'), out = opt('--out');
if (!chromium || !shadersDir || !out) {
  console.error('usage: node capture.mjs --chromium PATH --shaders DIR --query QUERY --out FILE [--png FILE]');
  process.exit(2);
}

const server = await startServer({ shadersDir });
const problems = [];
const browser = await puppeteer.launch({
  executablePath: chromium,
  headless: true,
  args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
         '--ignore-gpu-blocklist', '--disable-gpu-driver-bug-workarounds'],
});
try {
  const page = await browser.newPage();
  page.on('console', (m) => { if (m.type() === 'error') problems.push('console error: ' + m.text()); });
  page.on('pageerror', (e) => problems.push('page error: ' + e.message));
  page.on('requestfailed', (r) => problems.push('request failed: ' + r.url()));
  page.on('response', (r) => { if (r.status() >= 400) problems.push(`HTTP ${r.status()}: ${r.url()}`); });
  await page.goto(server.url + '?' + (opt('--query') ?? ''), { waitUntil: 'load' });
  await page.waitForFunction(() => window.surfgrad?.ready || window.surfgradError, { timeout: 120000 })
    .catch(() => problems.push('the page did not draw within 120 s'));
  if (problems.length === 0) {
    const { width, height, rgba } = await page.evaluate(() => {
      const canvas = document.querySelector('canvas');
      const gl = canvas.getContext('webgl2');
      const w = gl.drawingBufferWidth, h = gl.drawingBufferHeight;
      const px = new Uint8Array(w * h * 4);
      gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, px);
      // readPixels starts at the bottom row: flip to top first.
      const rows = new Uint8Array(w * h * 4);
      for (let y = 0; y < h; ++y) rows.set(px.subarray((h - 1 - y) * w * 4, (h - y) * w * 4), y * w * 4);
      let s = '';
      for (let i = 0; i < rows.length; i += 0x8000) s += String.fromCharCode(...rows.subarray(i, i + 0x8000));
      return { width: w, height: h, rgba: btoa(s) };
    });
    const header = Buffer.alloc(8);
    header.writeUInt32LE(width, 0);
    header.writeUInt32LE(height, 4);
    await writeFile(out + '.tmp', Buffer.concat([header, Buffer.from(rgba, 'base64')]));
    await rename(out + '.tmp', out);
    if (opt('--png')) await (await page.$('canvas')).screenshot({ path: opt('--png') });
  }
} finally {
  await browser.close();
  server.close();
}
if (problems.length) {
  console.error(problems.join('\n'));
  process.exit(1);
}
