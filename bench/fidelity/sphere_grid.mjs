// Writes the fidelity harness's generated model: a 5 x 5 grid of spheres, metallic 0..1 from left
// to right and roughness 0..1 from top to bottom (glTF 2.0 metallic-roughness, one material per
// sphere, copper base colour), as one .gltf with its buffer embedded (a data: URI), so that every
// renderer reads the same bytes. Deterministic: the same file every run.
//
//   node sphere_grid.mjs OUT.gltf
import fs from 'node:fs';

const n = 5, spacing = 2.4, rings = 24, segments = 48;
const positions = [], normals = [], indices = [];
for (let r = 0; r <= rings; ++r) {
  const v = r / rings, phi = v * Math.PI;
  for (let s = 0; s <= segments; ++s) {
    const u = s / segments, theta = u * 2 * Math.PI;
    const p = [Math.sin(phi) * Math.sin(theta), Math.cos(phi), Math.sin(phi) * Math.cos(theta)];
    positions.push(...p);
    normals.push(...p);
  }
}
for (let r = 0; r < rings; ++r)
  for (let s = 0; s < segments; ++s) {
    const a = r * (segments + 1) + s, b = a + segments + 1;
    if (r > 0) indices.push(a, b, a + 1);                  // counter-clockwise seen from outside
    if (r < rings - 1) indices.push(a + 1, b, b + 1);
  }

const pos = Float32Array.from(positions), nrm = Float32Array.from(normals), idx = Uint16Array.from(indices);
const bytes = Buffer.concat([Buffer.from(pos.buffer), Buffer.from(nrm.buffer), Buffer.from(idx.buffer)]);
const min = [-1, -1, -1], max = [1, 1, 1];
const gltf = {
  asset: {version: '2.0', generator: 'facet bench/fidelity/sphere_grid.mjs'},
  buffers: [{byteLength: bytes.length, uri: 'data:application/octet-stream;base64,' + bytes.toString('base64')}],
  bufferViews: [
    {buffer: 0, byteOffset: 0, byteLength: pos.byteLength, target: 34962},
    {buffer: 0, byteOffset: pos.byteLength, byteLength: nrm.byteLength, target: 34962},
    {buffer: 0, byteOffset: pos.byteLength + nrm.byteLength, byteLength: idx.byteLength, target: 34963},
  ],
  accessors: [
    {bufferView: 0, componentType: 5126, count: pos.length / 3, type: 'VEC3', min, max},
    {bufferView: 1, componentType: 5126, count: nrm.length / 3, type: 'VEC3'},
    {bufferView: 2, componentType: 5123, count: idx.length, type: 'SCALAR'},
  ],
  materials: [],
  meshes: [],
  nodes: [],
  scenes: [{nodes: []}],
  scene: 0,
};
for (let row = 0; row < n; ++row)
  for (let col = 0; col < n; ++col) {
    const metallic = col / (n - 1), roughness = row / (n - 1);
    const m = gltf.materials.length;
    gltf.materials.push({name: `metallic ${metallic} roughness ${roughness}`,
                         pbrMetallicRoughness: {baseColorFactor: [0.955, 0.638, 0.538, 1], metallicFactor: metallic,
                                                roughnessFactor: roughness}});
    gltf.meshes.push({primitives: [{attributes: {POSITION: 0, NORMAL: 1}, indices: 2, material: m}]});
    gltf.nodes.push({mesh: m, translation: [(col - (n - 1) / 2) * spacing, ((n - 1) / 2 - row) * spacing, 0]});
    gltf.scenes[0].nodes.push(gltf.nodes.length - 1);
  }
fs.writeFileSync(process.argv[2], JSON.stringify(gltf) + '\n');
