// Writes docs/FIDELITY.md from fidelity.mjs's fidelity.json (bench/fidelity/run): the camera
// rule, then per model the three images and the SSIM of facet and of f3d against model-viewer.
//
//   node report.mjs fidelity.json FIDELITY.md "facet VERSION" COMMIT SIZE
import fs from 'node:fs';

const [jsonPath, mdPath, version, commit, size] = process.argv.slice(2);
const rows = JSON.parse(fs.readFileSync(jsonPath, 'utf8'));
const f = (x) => (x == null ? 'failed' : x.toFixed(3));
const mean = (xs) => xs.reduce((a, b) => a + b, 0) / xs.length;
const facetSsim = rows.map((r) => r.ssim_facet_vs_model_viewer);
const f3dSsim = rows.filter((r) => r.ssim_f3d_vs_model_viewer != null).map((r) => r.ssim_f3d_vs_model_viewer);

let md = `# Fidelity: facet, <model-viewer> and f3d on the same glTF files

The web's reference for how a glTF model should look is \`<model-viewer>\` (three.js's
metallic-roughness PBR under an image-based light, Khronos PBR Neutral tone mapping); f3d is the
desktop's. \`bench/fidelity/run\` draws each model below with the same camera, size (${size} x ${size})
and white background in all three, and compares facet's and f3d's images with model-viewer's by SSIM
(\`facet diff --json\`: the mean over the colour channels of windowed SSIM, 1 = identical). Written by bench/fidelity/run at ${commit}
(${version}); rerun it after a change to \`lit\`.

| renderer | how it runs | settings |
|---|---|---|
| facet | \`facet render MODEL --shading lit --ssaa 2 --eye E --target T --fov F\` | today's \`lit\` |
| model-viewer 4.4 | headless Debian Chromium, SwiftShader WebGL, \`puppeteer-core\`, page and files served on 127.0.0.1 | \`environment-image="neutral" tone-mapping="neutral" shadow-intensity="0"\`, render scale pinned to 1 |
| f3d 1.3.1 | \`xvfb-run f3d MODEL --output ... --camera-position E --camera-focal-point T --camera-view-angle F\` | \`--fxaa --tone-mapping\`, its default lights |

## The camera

All three look from the same eye E at the same target T with the same vertical field of view F:

1. facet frames the model as for a thumbnail (azimuth 35, elevation 25, fov 45; README, "Automatic
   framing"): T = the centre of the axis-aligned bounds, distance D = r / sin(fov / 2) with r the
   largest distance of a vertex from T; \`facet render --print-config\` prints E and T.
2. model-viewer gets \`camera-target="Tx Ty Tz"\` (metres), \`camera-orbit="35deg 65deg Dm"\`
   (theta is facet's azimuth: both measure about +Y from +Z toward +X; phi is the polar angle,
   90 - elevation), \`field-of-view="45deg"\`, and its clamps opened (\`min/max-field-of-view\`,
   \`max-camera-orbit\` radius 2D: the default maximum radius would pull the camera in).
3. model-viewer widens the vertical field of view of a model whose bounds are wider than the canvas
   (ModelScene.adjustedFoV), so the camera it actually used is read back (\`getCameraTarget\`,
   \`getCameraOrbit\`, \`getFieldOfView\`): E = T + radius (sin phi sin theta, cos phi, sin phi cos theta).
   facet renders that camera (\`--eye --target --fov\`) and f3d too (\`--camera-*\`, view angle =
   vertical fov); the F column gives it.

## Results

SSIM against model-viewer, mean over ${rows.length} models: facet ${mean(facetSsim).toFixed(3)}, f3d ${
  f3dSsim.length ? mean(f3dSsim).toFixed(3) : 'n/a'}.

| model | F | SSIM facet | SSIM f3d | facet | model-viewer | f3d |
|---|---|---|---|---|---|---|
`;
for (const r of rows) {
  const img = (who) => `![${r.name} ${who}](images/fidelity/${r.name}.${who}.png)`;
  md += `| ${r.model} | ${r.camera.fov.toFixed(1)} | ${
    f(r.ssim_facet_vs_model_viewer)} | ${f(r.ssim_f3d_vs_model_viewer)} | ${img('facet')} | ${img('model-viewer')} | ${img('f3d')} |\n`;
}
md += `
Whole-process time per model in this run (ms; facet: load, environment, render, write; model-viewer:
the model in the already open page, the first one with Chromium's start; f3d: with Xvfb's start):
${rows.map((r) => `${r.name} facet ${r.ms.facet}, model-viewer ${r.ms.model_viewer}, f3d ${r.ms.f3d}`).join('; ')}.
Measured on the shared 2-core machine while others built: for orders of magnitude only.

The sphere grid is bench/fidelity/sphere_grid.mjs: metallic 0, 0.25 ... 1 from left to right,
roughness 0 ... 1 from top to bottom, copper base colour. In all three the highlight widens and dims
down each column; in facet and model-viewer the metals (right) take the environment's colour
tinted by the base colour, where f3d's metals, lit by its default lights without an environment,
turn black. What still separates facet from model-viewer: the environment (facet's built-in studio
is a grey room with four soft boxes, model-viewer's \`neutral\` is three.js's RoomEnvironment; the
reflections in the smooth metals show it), and model-viewer's slightly brighter overall exposure.
`;
fs.writeFileSync(mdPath, md);
