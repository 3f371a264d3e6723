// Fidelity harness (bench/fidelity/run): the same glTF models, camera and neutral light drawn by
// facet (`lit`), by <model-viewer> (three.js PBR, the web's reference) in Debian's headless
// Chromium, and by f3d; the three images per model go to OUT_DIR, SSIM facet vs model-viewer (facet
// diff --json) to OUT_DIR/fidelity.json. Not a test: numbers for docs/FIDELITY.md.
//
// The camera: facet frames the model (README, "Automatic framing": target = bounding-box centre,
// eye at the framing distance along azimuth/elevation, vertical fov), --print-config prints that
// eye and target, and model-viewer is given them as camera-target, camera-orbit "AZdeg (90-EL)deg
// Dm" and field-of-view, with its clamps opened. model-viewer may still widen the field of view
// for a model wider than the canvas (ModelScene.adjustedFoV), so the camera it really used is read
// back (getCameraOrbit, getCameraTarget, getFieldOfView) and facet and f3d then render that camera
// explicitly (--eye/--target/--fov; --camera-position/-focal-point/-view-angle).
//
//   node fidelity.mjs --facet BIN --out DIR [--size N] [--models a.glb,b.gltf] [--azimuth 35 --elevation 25 --fov 45]
//                     [--modules DIR]
// DIR holds node_modules with @google/model-viewer and puppeteer-core; by default the folder where
// `scripts/setup --peers` installs them (${XDG_CACHE_HOME:-~/.cache}/facet/peers).
import {spawnSync} from 'node:child_process';
import fs from 'node:fs';
import http from 'node:http';
import {createRequire} from 'node:module';
import os from 'node:os';
import path from 'node:path';

const args = Object.fromEntries(process.argv.slice(2).reduce((pairs, a, i, all) => {
  if (a.startsWith('--')) pairs.push([a.slice(2), all[i + 1]]);
  return pairs;
}, []));
const modules = args.modules || path.join(process.env.XDG_CACHE_HOME || path.join(os.homedir(), '.cache'), 'facet', 'peers');
const require = createRequire(path.join(path.resolve(modules), 'node_modules', 'x.js'));
const puppeteer = require('puppeteer-core');
const facet = args.facet;
const outDir = path.resolve(args.out);
const size = Number(args.size || 400);
const azimuth = Number(args.azimuth ?? 35), elevation = Number(args.elevation ?? 25), fov = Number(args.fov ?? 45);
const background = [1, 1, 1];  // white behind all three
const models = args.models.split(',');
fs.mkdirSync(outDir, {recursive: true});

function run(cmd, argv, opts = {}) {
  const r = spawnSync(cmd, argv, {encoding: 'utf8', ...opts});
  if (r.status !== 0 && !opts.allowFail)
    throw new Error(`${cmd} ${argv.join(' ')}: exit ${r.status}\n${r.stderr}`);
  return r;
}
const vec = (text) => text.split(',').map(Number);

// facet's framing of the model, from --print-config.
function facetFraming(model) {
  const out = run(facet, ['render', model, '--print-config', '--size', `${size}x${size}`, '--azimuth', azimuth,
                          '--elevation', elevation, '--fov', fov].map(String)).stdout;
  const get = (k) => out.match(new RegExp(`^${k} = (.*)$`, 'm'))[1];
  return {eye: vec(get('eye')), target: vec(get('target'))};
}

// A static HTTP server on 127.0.0.1 (a free port): the page, model-viewer's script and the model
// folders, each under its own prefix. Nothing else is served.
function serve(routes) {
  const types = {'.html': 'text/html', '.js': 'text/javascript', '.gltf': 'model/gltf+json',
                 '.glb': 'model/gltf-binary', '.bin': 'application/octet-stream', '.png': 'image/png',
                 '.jpg': 'image/jpeg', '.jpeg': 'image/jpeg'};
  const server = http.createServer((req, res) => {
    const url = decodeURIComponent(new URL(req.url, 'http://x').pathname);
    for (const [prefix, dir] of Object.entries(routes)) {
      if (!url.startsWith(prefix)) continue;
      const file = path.join(dir, url.slice(prefix.length));
      if (!file.startsWith(dir) || !fs.existsSync(file) || !fs.statSync(file).isFile()) break;
      res.writeHead(200, {'Content-Type': types[path.extname(file).toLowerCase()] || 'application/octet-stream'});
      fs.createReadStream(file).pipe(res);
      return;
    }
    res.writeHead(404).end();
  });
  return new Promise((resolve) => server.listen(0, '127.0.0.1', () => resolve(server)));
}

const page_html = (bg) => `<!doctype html><html><head><style>
  html, body { margin: 0; background: rgb(${bg.map((c) => c * 255).join(',')}); }
  model-viewer { width: ${size}px; height: ${size}px; --progress-bar-height: 0; background-color: transparent; }
</style><script type="module" src="/mv/model-viewer.min.js"></script></head>
<body><model-viewer id="mv" environment-image="neutral" tone-mapping="neutral" shadow-intensity="0"
  interaction-prompt="none" min-field-of-view="1deg" max-field-of-view="179deg"></model-viewer></body></html>`;

async function main() {
  const work = fs.mkdtempSync(path.join(os.tmpdir(), 'facet-fidelity-'));
  fs.writeFileSync(path.join(work, 'index.html'), page_html(background));
  const mvDist = path.dirname(require.resolve('@google/model-viewer/dist/model-viewer.min.js'));
  const routes = {'/mv/': mvDist, '/page/': work};
  models.forEach((m, i) => { routes[`/m${i}/`] = path.dirname(path.resolve(m)); });
  const server = await serve(routes);
  const port = server.address().port;
  const browser = await puppeteer.launch({
    executablePath: '/usr/bin/chromium',
    headless: true,
    args: ['--no-sandbox', '--headless=new', '--use-gl=angle', `--use-angle=${process.env.FIDELITY_ANGLE || 'swiftshader'}`,
           '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist', '--no-first-run',
           '--disable-background-networking', '--disable-component-update', '--disable-sync', '--disable-quic',
           `--window-size=${size + 64},${size + 64}`],
  });
  const results = [];
  try {
    const page = await browser.newPage();
    if (process.env.FIDELITY_DEBUG) page.on('console', (m) => console.error('page:', m.text()));
    await page.setViewport({width: size + 64, height: size + 64, deviceScaleFactor: 1});
    await page.goto(`http://127.0.0.1:${port}/page/index.html`);
    await page.waitForFunction(() => customElements.get('model-viewer') !== undefined);
    await page.evaluate(() => { customElements.get('model-viewer').minimumRenderScale = 1; });
    for (const [i, model] of models.entries()) {
      const name = path.basename(model).replace(/\.(gltf|glb)$/i, '');
      const {eye, target} = facetFraming(model);
      const d = [0, 1, 2].map((k) => eye[k] - target[k]);
      const radius = Math.hypot(...d);
      const started = Date.now();
      const camera = await page.evaluate(async (src, target, radius, orbit, fov) => {
        const mv = document.getElementById('mv');
        mv.setAttribute('camera-target', `${target[0]}m ${target[1]}m ${target[2]}m`);
        mv.setAttribute('max-camera-orbit', `auto auto ${2 * radius}m`);
        mv.setAttribute('camera-orbit', orbit);
        mv.setAttribute('field-of-view', `${fov}deg`);
        const loaded = new Promise((ok, fail) => {
          mv.addEventListener('load', ok, {once: true});
          mv.addEventListener('error', (e) => fail(new Error(JSON.stringify(e.detail))), {once: true});
        });
        mv.src = src;
        await loaded;
        mv.jumpCameraToGoal();
        for (let f = 0; f < 10; ++f) await new Promise((r) => requestAnimationFrame(r));
        const o = mv.getCameraOrbit(), t = mv.getCameraTarget();
        return {theta: o.theta, phi: o.phi, radius: o.radius, target: [t.x, t.y, t.z], fov: mv.getFieldOfView()};
      }, `/m${i}/${encodeURIComponent(path.basename(model))}`, target, radius,
         `${azimuth}deg ${90 - elevation}deg ${radius}m`, fov);
      const mvMs = Date.now() - started;
      const mvPng = path.join(outDir, `${name}.model-viewer.png`);
      await page.screenshot({path: mvPng, clip: {x: 0, y: 0, width: size, height: size}});

      // The camera model-viewer used, for facet and f3d.
      const s = Math.sin(camera.phi), r = camera.radius;
      const eyeUsed = [camera.target[0] + r * s * Math.sin(camera.theta), camera.target[1] + r * Math.cos(camera.phi),
                       camera.target[2] + r * s * Math.cos(camera.theta)];
      const fmt = (v) => v.map((x) => x.toPrecision(9)).join(',');
      const facetPng = path.join(outDir, `${name}.facet.png`);
      let t0 = Date.now();
      run(facet, ['render', model, '-o', facetPng, '--size', `${size}x${size}`, '--shading', 'lit', '--ssaa', '2',
                  '--eye', fmt(eyeUsed), '--target', fmt(camera.target), '--fov', String(camera.fov),
                  '--background', background.join(',')]);
      const facetMs = Date.now() - t0;
      const f3dPng = path.join(outDir, `${name}.f3d.png`);
      t0 = Date.now();
      const f3d = run('xvfb-run', ['-a', 'f3d', model, '--output', f3dPng, '--resolution', `${size},${size}`,
                                   '--camera-position', fmt(eyeUsed), '--camera-focal-point', fmt(camera.target),
                                   '--camera-view-up', '0,1,0', '--camera-view-angle', String(camera.fov),
                                   '--bg-color', background.join(','), '--fxaa', '--tone-mapping',
                                   '--up', '+Y', '--grid=false'].map(String), {allowFail: true});
      const f3dMs = Date.now() - t0;
      const diff = JSON.parse(run(facet, ['diff', facetPng, mvPng, '--json'], {allowFail: true}).stdout);
      const f3dDiff = f3d.status === 0 ? JSON.parse(run(facet, ['diff', f3dPng, mvPng, '--json'], {allowFail: true}).stdout) : null;
      const assimp = '/usr/share/assimp/models/';
      const row = {model: path.resolve(model).startsWith(assimp) ? path.resolve(model).slice(assimp.length)
                                                                 : `${path.basename(model)} (generated)`, name,
                   camera: {eye: eyeUsed, target: camera.target, fov: camera.fov, asked_fov: fov},
                   ssim_facet_vs_model_viewer: diff.ssim, psnr_facet_vs_model_viewer: diff.psnr_db ?? diff.psnr,
                   ssim_f3d_vs_model_viewer: f3dDiff ? f3dDiff.ssim : null,
                   f3d_status: f3d.status, ms: {model_viewer: mvMs, facet: facetMs, f3d: f3dMs}};
      results.push(row);
      console.error(`fidelity: ${name}: SSIM facet/model-viewer ${diff.ssim?.toFixed(4)}, f3d/model-viewer ${
                    f3dDiff ? f3dDiff.ssim?.toFixed(4) : 'failed'} (fov ${camera.fov.toFixed(2)})`);
    }
  } finally {
    await browser.close();
    server.close();
    fs.rmSync(work, {recursive: true, force: true});
  }
  fs.writeFileSync(path.join(outDir, 'fidelity.json'), JSON.stringify(results, null, 1) + '\n');
}

main().catch((e) => { console.error(e); process.exit(1); });
