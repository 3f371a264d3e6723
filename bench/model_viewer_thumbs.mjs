// Collections benchmark, the <model-viewer> side (bench/collection_bench.py runs it; not a test):
// thumbnails of glTF files by Google's <model-viewer> (three.js) in Debian's headless Chromium, one
// browser and one page for the whole list, as a batch thumbnailer built on it would run. In: a JSON
// list of {"path", "out"}, a size; out: a PNG per model that loaded, and one line per model on
// stdout ({"path", "ok", "error"}). Everything is served from 127.0.0.1 (no CDN).
//
//   node bench/model_viewer_thumbs.mjs [--modules DIR] --list LIST.json --size 256 [--chromium PATH]
//
// DIR holds node_modules with @google/model-viewer and puppeteer-core; by default the folder where
// `scripts/setup --peers` installs them (${XDG_CACHE_HOME:-~/.cache}/facet/peers).
import fs from "node:fs";
import http from "node:http";
import os from "node:os";
import path from "node:path";
import { createRequire } from "node:module";

const args = Object.fromEntries(
  process.argv.slice(2).reduce((pairs, a, i, all) => (a.startsWith("--") ? [...pairs, [a.slice(2), all[i + 1]]] : pairs), []));
const size = Number(args.size || 256);
const list = JSON.parse(fs.readFileSync(args.list, "utf8"));
const modules = args.modules || path.join(process.env.XDG_CACHE_HOME || path.join(os.homedir(), ".cache"), "facet", "peers");
const require = createRequire(path.join(path.resolve(modules), "node_modules", "x.js"));
const puppeteer = require("puppeteer-core");
const viewerScript = require.resolve("@google/model-viewer/dist/model-viewer.min.js");

// The models' folders are the only ones served, besides the page and the script.
const allowed = new Set(list.map((m) => path.dirname(path.resolve(m.path))));
const types = { ".gltf": "model/gltf+json", ".glb": "model/gltf-binary", ".bin": "application/octet-stream",
                ".png": "image/png", ".jpg": "image/jpeg", ".jpeg": "image/jpeg", ".js": "text/javascript" };
const page_html = `<!doctype html><html><body style="margin:0;background:#fff">
<script type="module" src="/model-viewer.min.js"></script>
<model-viewer id="mv" style="width:${size}px;height:${size}px;display:block" interaction-prompt="none"
  disable-zoom disable-pan environment-image="neutral" shadow-intensity="0"></model-viewer></body></html>`;
const server = http.createServer((req, res) => {
  const url = decodeURIComponent(new URL(req.url, "http://x").pathname);
  let file = null;
  if (url === "/") return res.writeHead(200, { "content-type": "text/html" }).end(page_html);
  if (url === "/model-viewer.min.js") file = viewerScript;
  else if (url.startsWith("/fs/")) {
    const p = path.resolve("/" + url.slice(4));
    if ([...allowed].some((dir) => p.startsWith(dir + path.sep))) file = p;
  }
  if (!file || !fs.existsSync(file) || !fs.statSync(file).isFile()) return res.writeHead(404).end();
  res.writeHead(200, { "content-type": types[path.extname(file).toLowerCase()] || "application/octet-stream" });
  fs.createReadStream(file).pipe(res);
});
await new Promise((ok) => server.listen(0, "127.0.0.1", ok));
const origin = `http://127.0.0.1:${server.address().port}`;

const browser = await puppeteer.launch({
  executablePath: args.chromium || "/usr/bin/chromium",
  headless: "new",
  // Mesa llvmpipe through ANGLE's EGL back end: the faster of the two software paths (peers.md).
  args: ["--no-sandbox", "--use-gl=angle", "--use-angle=gl-egl", "--ignore-gpu-blocklist", "--no-first-run",
         "--disable-background-timer-throttling", "--disable-renderer-backgrounding"],
});
const page = await browser.newPage();
await page.setViewport({ width: size, height: size, deviceScaleFactor: 1 });
await page.goto(origin + "/");
await page.waitForFunction(() => customElements.get("model-viewer") !== undefined);

for (const m of list) {
  const src = origin + "/fs" + path.resolve(m.path).split(path.sep).map(encodeURIComponent).join("/");
  let result;
  try {
    result = await page.evaluate(async (src) => {
      const mv = document.getElementById("mv");
      mv.minimumRenderScale = 1;  // it lowers its resolution when frames are slow: not here
      const loaded = new Promise((ok) => {
        const done = (e) => { mv.removeEventListener("load", done); mv.removeEventListener("error", done); ok(e.type); };
        mv.addEventListener("load", done);
        mv.addEventListener("error", done);
      });
      mv.src = src;
      const outcome = await Promise.race([loaded, new Promise((ok) => setTimeout(() => ok("timeout"), 60000))]);
      if (outcome !== "load") return { ok: false, error: outcome };
      for (let i = 0; i < 3; ++i) await new Promise((ok) => requestAnimationFrame(ok));
      const blob = await mv.toBlob({ mimeType: "image/png", idealAspect: false });
      const bytes = new Uint8Array(await blob.arrayBuffer());
      let text = "";
      for (let i = 0; i < bytes.length; i += 0x8000) text += String.fromCharCode(...bytes.subarray(i, i + 0x8000));
      return { ok: true, png: btoa(text) };
    }, src);
  } catch (e) {
    result = { ok: false, error: String(e).slice(0, 200) };
  }
  if (result.ok) fs.writeFileSync(m.out, Buffer.from(result.png, "base64"));
  process.stdout.write(JSON.stringify({ path: m.path, ok: result.ok, error: result.error || null }) + "\n");
}
await browser.close();
server.close();
