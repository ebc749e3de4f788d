// Loads a .glb with three.js's GLTFLoader (npm `three`, pinned in package.json), plays its
// first animation with an AnimationMixer to the given times, and prints, for every named
// mesh node, its world matrix (column-major, 16 numbers) at each time, as JSON:
//   { "clipDuration": s, "times": [...], "nodes": { name: [[16 numbers] per time] } }
// Usage: node tests/gltf/three_sample.mjs FILE.glb t0 t1 ...
// Exit status: 2 when the file does not load, 3 when three is not installed.
import { readFileSync } from 'node:fs';

let THREE, GLTFLoader;
try {
  THREE = await import('three');
  ({ GLTFLoader } = await import('three/examples/jsm/loaders/GLTFLoader.js'));
} catch (e) {
  console.error(`three is not installed in tests/gltf/node_modules (run scripts/setup-node.sh): ${e.message}`);
  process.exit(3);
}

const [file, ...timeArgs] = process.argv.slice(2);
const times = timeArgs.map(Number);
const bytes = readFileSync(file);
const buffer = bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength);

let gltf;
try {
  gltf = await new GLTFLoader().parseAsync(buffer, '');
} catch (e) {
  console.error(`three.js GLTFLoader cannot load ${file}: ${e}`);
  process.exit(2);
}

const root = gltf.scene;
const mixer = new THREE.AnimationMixer(root);
const clip = gltf.animations[0];
if (clip) {
  const action = mixer.clipAction(clip);
  action.setLoop(THREE.LoopOnce, 1);
  action.clampWhenFinished = true;
  action.play();
}

const meshes = [];
root.traverse((o) => { if (o.isMesh) meshes.push(o); });
const nodes = {};
for (const m of meshes) nodes[m.name] = [];
for (const t of times) {
  mixer.setTime(t);
  root.updateMatrixWorld(true);
  for (const m of meshes) nodes[m.name].push(Array.from(m.matrixWorld.elements));
}
console.log(JSON.stringify({ clipDuration: clip ? clip.duration : null, times, nodes }));
