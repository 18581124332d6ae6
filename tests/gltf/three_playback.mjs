// Loads a drape .glb with three.js's GLTFLoader and plays its animation with an AnimationMixer,
// as a web page would (without drawing: no WebGL here), and checks that at each given frame the
// mesh three.js morphs to (base + Σ influence · target, what its shader computes) is the run's
// own OBJ frame. Exits 1 on a mismatch, 77 (skipped, for CTest) if three.js is not installed
// and $CI is not set.
// Usage: node three_playback.mjs RUN.glb FRAMES_DIR FPS FRAME...
import { readFileSync } from 'node:fs';
import { createRequire } from 'node:module';

const require = createRequire(import.meta.url);
try {
  require.resolve('three');
} catch {
  console.error('three_playback: three is not installed in tests/gltf; run bash scripts/deps.sh');
  process.exit(process.env.CI ? 1 : 77);
}
const THREE = await import('three');
const { GLTFLoader } = await import('three/examples/jsm/loaders/GLTFLoader.js');

const [glb, framesDir, fps, ...frames] = process.argv.slice(2);
const bytes = readFileSync(glb);
const gltf = await new GLTFLoader().parseAsync(
  bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength), '');

let cloth = null;
gltf.scene.traverse((o) => {
  if (o.isMesh && o.morphTargetInfluences) cloth = o;
});
if (!cloth) {
  console.error('three_playback: no mesh with morph targets');
  process.exit(1);
}
const clip = gltf.animations[0];
console.log(`three_playback: three r${THREE.REVISION}: ${cloth.name}, ` +
            `${cloth.geometry.attributes.position.count} vertices, ` +
            `${cloth.morphTargetInfluences.length} morph targets; clip of ${clip.duration} s`);

const mixer = new THREE.AnimationMixer(gltf.scene);
const action = mixer.clipAction(clip);
action.setLoop(THREE.LoopOnce);  // hold the last frame at the end, not wrap to the first
action.clampWhenFinished = true;
action.play();

const base = cloth.geometry.attributes.position.array;
const targets = cloth.geometry.morphAttributes.position;
let failed = false;
for (const frame of frames.map(Number)) {
  mixer.setTime(frame / Number(fps));
  const weights = cloth.morphTargetInfluences;
  const obj = readFileSync(`${framesDir}/frame_${String(frame).padStart(5, '0')}.obj`, 'utf8')
    .split('\n').filter((l) => l.startsWith('v '))
    .flatMap((l) => l.split(' ').slice(1, 4).map(Number));
  let worst = 0;
  for (let i = 0; i < base.length; ++i) {
    let x = base[i];
    for (let t = 0; t < targets.length; ++t) x += weights[t] * targets[t].array[i];
    worst = Math.max(worst, Math.abs(x - obj[i]));
  }
  console.log(`three_playback: frame ${frame}: largest difference ${worst.toExponential(2)} m`);
  if (!(worst < 1e-6)) failed = true;
}
process.exit(failed ? 1 : 0);
