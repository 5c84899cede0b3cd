#!/usr/bin/env node
// SPDX-License-Identifier: MIT
//
// Poses glTF files (.glb or .gltf) with three.js, a second real client of what DeepCut writes:
// GLTFLoader reads the file, AnimationMixer plays one clip at the given times, and every mesh
// primitive's glTF vertices are printed at their posed world positions (morph targets, then
// skinning, then the mesh's world matrix: three's own `getVertexPosition`), with the bounds.
//
//   node scripts/pose_three.mjs [--animation A] [--times T1,T2,...] FILE [FILE...]
//   node scripts/pose_three.mjs --request REQUEST.json
//   node scripts/pose_three.mjs --check      (exit 0 when three.js loads; tests skip otherwise)
//
// A request is a JSON array of {"file": PATH, "animation": A, "times": [T...], "unit_rotations":
// B} (one node process for many files). Animation -1 (the default) is the rest pose; times
// default to [0]. With "unit_rotations" true, rotation keys that are not unit quaternions are
// normalised first, as the project's reader does (for input files; exports are posed as stored).
// Prints one JSON array on stdout, one entry per file:
//   {"file", "error"?, "animations": [{"name", "duration"}], "normalised_rotation_keys"?,
//    "instances": [{"node", "mesh", "primitive", "skinned", "targets", "vertices", "indices": [...]}],
//    "poses": [{"time", "min": [x,y,z], "max": [x,y,z],
//               "positions": [[x0,y0,z0,x1,...] per instance], "weights": [[...] per instance]}]}
// An instance is one primitive drawn by one node of the default scene; "indices" are its
// triangles as glTF vertex indices (three's index, or 0..n-1 when the file had none).
//
// three.js is the npm package `three`, installed by scripts/deps.sh into build/tools; set
// DEEPCUT_THREE_DIR to use another copy (the folder holding the package's package.json).
// Textures are never decoded (only geometry matters): every texture is an empty Texture, so no
// DOM or image decoder is needed. EXT_meshopt_compression is decoded by three's MeshoptDecoder,
// KHR_draco_mesh_compression by three's DRACOLoader, its worker run on node's worker_threads.
// three.js skins with four influences; a primitive with JOINTS_1/WEIGHTS_1 is skinned here
// with all eight by three's own bone matrices, the same sum three's shader makes for four.
//
// Exit status: 0 every file posed, 1 some file could not be read or posed (its entry has
// "error"), 2 bad arguments or three.js missing.

import fs from 'node:fs';
import path from 'node:path';
import { pathToFileURL, fileURLToPath } from 'node:url';
import { resolveObjectURL } from 'node:buffer';
import { Worker as ThreadWorker } from 'node:worker_threads';

const scriptDir = path.dirname(fileURLToPath(import.meta.url));
const repoRoot = path.resolve(scriptDir, '..');

async function loadThree() {
  const dir = process.env.DEEPCUT_THREE_DIR
    ? path.resolve(process.env.DEEPCUT_THREE_DIR)
    : path.join(repoRoot, 'build', 'tools', 'node_modules', 'three');
  if (!fs.existsSync(path.join(dir, 'package.json'))) {
    console.error(`pose_three: three.js not found in ${dir}`);
    console.error('pose_three: install it with: bash scripts/deps.sh (or set DEEPCUT_THREE_DIR)');
    return null;
  }
  const url = (rel) => pathToFileURL(path.join(dir, rel)).href;
  const THREE = await import(url('build/three.module.js'));
  const { GLTFLoader } = await import(url('examples/jsm/loaders/GLTFLoader.js'));
  const { DRACOLoader } = await import(url('examples/jsm/loaders/DRACOLoader.js'));
  const { MeshoptDecoder } = await import(url('examples/jsm/libs/meshopt_decoder.module.js'));
  return { THREE, GLTFLoader, DRACOLoader, MeshoptDecoder, dir };
}

// The web Worker that DRACOLoader starts, on a node worker thread: the worker's source (the
// decoder and three's worker function, a blob: URL) runs with `self`, `postMessage` and
// `onmessage` wired to the thread's port. Messages wait until the source is read.
class BlobWorker {
  constructor(url) {
    this.onmessage = null;
    this.queue = [];
    this.thread = null;
    resolveObjectURL(url).text().then((source) => {
      const prelude = [
        "const { parentPort } = require('node:worker_threads');",
        'globalThis.self = globalThis;',
        'globalThis.postMessage = (m, transfer) => parentPort.postMessage(m, transfer);',
        "parentPort.on('message', (data) => globalThis.onmessage({ data }));",
      ].join('\n');
      this.thread = new ThreadWorker(prelude + '\n' + source, { eval: true });
      this.thread.on('message', (data) => this.onmessage && this.onmessage({ data }));
      for (const [m, t] of this.queue) this.thread.postMessage(m, t);
      this.queue = [];
    });
  }
  postMessage(message, transfer) {
    if (this.thread) this.thread.postMessage(message, transfer);
    else this.queue.push([message, transfer]);
  }
  terminate() {
    if (this.thread) this.thread.terminate();
  }
}

// three's DRACOLoader reading its decoder (wasm) from the installed package's files.
function installDraco(three) {
  if (typeof globalThis.Worker === 'undefined') globalThis.Worker = BlobWorker;
  const loader = new three.DRACOLoader();
  loader.setDecoderPath(path.join(three.dir, 'examples', 'jsm', 'libs', 'draco') + path.sep);
  loader.setWorkerLimit(1);
  loader._loadLibrary = (file, responseType) => fs.promises.readFile(file).then((bytes) =>
    responseType === 'text' ? bytes.toString('utf8') : bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength));
  return loader;
}

// Returns true when `child` is `parent` itself or lies inside it.
function isInside(parent, child) {
  const rel = path.relative(parent, child);
  return rel === '' || (!rel.startsWith('..') && !path.isAbsolute(rel));
}

// A .gltf's JSON with every relative buffer URI replaced by a data: URI of the file's bytes
// (three fetches buffers, and node's fetch reads no files). Images are left alone: never loaded.
// (FileLoader reports progress with the DOM's ProgressEvent, which node lacks: a plain Event.)
function inlineBuffers(file) {
  if (typeof globalThis.ProgressEvent === 'undefined') {
    globalThis.ProgressEvent = class ProgressEvent extends Event {
      constructor(type, init = {}) {
        super(type);
        Object.assign(this, init);
      }
    };
  }
  const json = JSON.parse(fs.readFileSync(file, 'utf8'));
  const baseDir = fs.realpathSync(path.dirname(path.resolve(file)));
  for (const buffer of json.buffers || []) {
    if (buffer.uri === undefined || /^[a-zA-Z][a-zA-Z0-9+.-]*:/.test(buffer.uri)) continue;
    const target = fs.realpathSync(path.resolve(baseDir, decodeURIComponent(buffer.uri)));
    if (!isInside(baseDir, target)) throw new Error(`buffer URI ${buffer.uri} points outside ${baseDir}`);
    buffer.uri = 'data:application/octet-stream;base64,' + fs.readFileSync(target).toString('base64');
  }
  return JSON.stringify(json);
}

// A GLTFLoader plugin that answers every texture with an empty Texture: nothing is decoded.
function textureStub(THREE) {
  return () => ({
    name: 'DEEPCUT_texture_stub',
    loadTexture: () => Promise.resolve(new THREE.Texture()),
  });
}

async function loadGltf(three, file, draco) {
  const loader = new three.GLTFLoader();
  loader.setMeshoptDecoder(three.MeshoptDecoder);
  loader.setDRACOLoader(draco);
  loader.register(textureStub(three.THREE));
  const data = path.extname(file).toLowerCase() === '.gltf'
    ? inlineBuffers(file)
    : new Uint8Array(fs.readFileSync(file)).buffer;
  return loader.parseAsync(data, path.dirname(path.resolve(file)) + path.sep);
}

// glTF node index of a mesh object: its own association, else its nearest ancestor's (a
// multi-primitive mesh is a Group of Meshes, a node with a mesh and more is a Group).
function nodeIndexOf(associations, object) {
  for (let o = object; o; o = o.parent) {
    const a = associations.get(o);
    if (a && a.nodes !== undefined) return a.nodes;
  }
  return -1;
}

function describeInstances(gltf) {
  if (!gltf.scene) throw new Error('the file has no scene to draw');
  const associations = gltf.parser.associations;
  const instances = [];
  gltf.scene.traverse((o) => {
    if (!o.isMesh) return;
    const a = associations.get(o) || {};
    const geometry = o.geometry;
    const count = geometry.attributes.position.count;
    const indices = geometry.index ? Array.from(geometry.index.array) : Array.from({ length: count }, (_, i) => i);
    instances.push({
      object: o,
      info: {
        node: nodeIndexOf(associations, o),
        mesh: a.meshes === undefined ? -1 : a.meshes,
        primitive: a.primitives === undefined ? 0 : a.primitives,
        skinned: o.isSkinnedMesh === true,
        targets: (geometry.morphAttributes.position || []).length,
        vertices: count,
        indices,
      },
    });
  });
  instances.sort((x, y) => x.info.node - y.info.node || x.info.primitive - y.info.primitive);
  return instances;
}

// Skins `target` (morphed bind position of vertex i) with every influence of JOINTS_0/1 and
// WEIGHTS_0/1. three normalised the first four weights alone (normalizeSkinWeights), so they
// are scaled back by what the second four leave of 1.
function skinEight(THREE, mesh, i, target) {
  const g = mesh.geometry;
  const sets = [[g.attributes.skinIndex, g.attributes.skinWeight], [g.attributes.joints_1, g.attributes.weights_1]];
  let rest = 1;
  for (let c = 0; c < 4; ++c) rest -= sets[1][1].getComponent(i, c);
  const base = new THREE.Vector4(target.x, target.y, target.z, 1).applyMatrix4(mesh.bindMatrix);
  const sum = new THREE.Vector4(0, 0, 0, 0);
  const m = new THREE.Matrix4();
  for (let s = 0; s < 2; ++s) {
    for (let c = 0; c < 4; ++c) {
      const w = sets[s][1].getComponent(i, c) * (s === 0 ? rest : 1);
      if (w === 0) continue;
      const bone = sets[s][0].getComponent(i, c);
      m.multiplyMatrices(mesh.skeleton.bones[bone].matrixWorld, mesh.skeleton.boneInverses[bone]);
      sum.addScaledVector(new THREE.Vector4().copy(base).applyMatrix4(m), w);
    }
  }
  target.set(sum.x, sum.y, sum.z).applyMatrix4(mesh.bindMatrixInverse);
}

// Nine significant digits: every float32 exactly, a 1e-9 relative error for a double, and a
// third of the text of a double's shortest form.
function digits9(x) {
  return Number(x.toPrecision(9));
}

function posedPositions(THREE, mesh) {
  const n = mesh.geometry.attributes.position.count;
  const eight = mesh.isSkinnedMesh && mesh.geometry.attributes.joints_1 && mesh.geometry.attributes.weights_1;
  const out = new Array(3 * n);
  const v = new THREE.Vector3();
  for (let i = 0; i < n; ++i) {
    if (eight) {
      THREE.Mesh.prototype.getVertexPosition.call(mesh, i, v);  // morphs only
      skinEight(THREE, mesh, i, v);
    } else {
      mesh.getVertexPosition(i, v);  // morphs, then skinning for a SkinnedMesh
    }
    v.applyMatrix4(mesh.matrixWorld);
    out[3 * i] = digits9(v.x);
    out[3 * i + 1] = digits9(v.y);
    out[3 * i + 2] = digits9(v.z);
  }
  return out;
}

// Sets the scene to `time` of clip `clip` (null: rest pose), clamped to the clip's end.
function setPose(THREE, gltf, mixer, clip, time) {
  if (clip) {
    mixer.stopAllAction();
    const action = mixer.clipAction(clip);
    action.setLoop(THREE.LoopOnce, 1);
    action.clampWhenFinished = true;
    action.reset().play();
    mixer.setTime(Math.max(0, time));
  }
  gltf.scene.updateMatrixWorld(true);
  gltf.scene.traverse((o) => {
    if (o.isSkinnedMesh) o.skeleton.update();
  });
}

function poseOne(three, gltf, instances, animation, time) {
  const { THREE } = three;
  const clip = animation >= 0 ? gltf.animations[animation] : null;
  if (animation >= 0 && !clip) throw new Error(`animation ${animation} out of range (${gltf.animations.length} clips)`);
  const mixer = new THREE.AnimationMixer(gltf.scene);
  setPose(THREE, gltf, mixer, clip, time);
  const min = [Infinity, Infinity, Infinity];
  const max = [-Infinity, -Infinity, -Infinity];
  const positions = [];
  const weights = [];
  for (const { object } of instances) {
    const p = posedPositions(THREE, object);
    for (let i = 0; i < p.length; ++i) {
      min[i % 3] = Math.min(min[i % 3], p[i]);
      max[i % 3] = Math.max(max[i % 3], p[i]);
    }
    positions.push(p);
    weights.push(Array.from(object.morphTargetInfluences || []));
  }
  mixer.stopAllAction();
  mixer.uncacheRoot(gltf.scene);
  return { time, min, max, positions, weights };
}

// Makes every rotation key of `clip` a unit quaternion, as the project's reader does (glTF
// requires unit rotations; three.js interpolates the keys as stored). For cubic splines only
// the values, not the tangents. Returns how many keys changed.
function unitRotations(clip) {
  let changed = 0;
  for (const track of clip.tracks) {
    if (!track.name.endsWith('.quaternion')) continue;
    const keys = track.times.length;
    const stride = track.values.length === 12 * keys ? 12 : 4;
    const offset = stride === 12 ? 4 : 0;
    for (let k = 0; k < keys; ++k) {
      const q = track.values.subarray(stride * k + offset, stride * k + offset + 4);
      const len = Math.hypot(q[0], q[1], q[2], q[3]);
      if (Math.abs(len - 1) <= 1e-6) continue;
      ++changed;
      if (len < 1e-12 || !Number.isFinite(len)) q.set([0, 0, 0, 1]);
      else for (let i = 0; i < 4; ++i) q[i] /= len;
    }
  }
  return changed;
}

async function poseFile(three, draco, request) {
  const entry = { file: request.file };
  try {
    const gltf = await loadGltf(three, request.file, draco);
    const instances = describeInstances(gltf);
    entry.animations = gltf.animations.map((a) => ({ name: a.name, duration: a.duration }));
    entry.instances = instances.map((x) => x.info);
    const animation = request.animation === undefined ? -1 : request.animation;
    const times = request.times && request.times.length ? request.times : [0];
    if (request.unit_rotations && animation >= 0 && gltf.animations[animation]) {
      entry.normalised_rotation_keys = unitRotations(gltf.animations[animation]);
    }
    entry.poses = times.map((t) => poseOne(three, gltf, instances, animation, t));
  } catch (err) {
    entry.error = String(err && err.message ? err.message : err);
  }
  return entry;
}

function parseArgs(argv) {
  let animation = -1;
  let times = [0];
  const files = [];
  for (let i = 0; i < argv.length; ++i) {
    const a = argv[i];
    if (a === '--request') return JSON.parse(fs.readFileSync(argv[++i], 'utf8'));
    if (a === '--animation') animation = Number(argv[++i]);
    else if (a === '--times') times = String(argv[++i]).split(',').map(Number);
    else if (a.startsWith('-')) throw new Error(`unknown option ${a}`);
    else files.push(a);
  }
  if (!Number.isInteger(animation) || times.some((t) => !Number.isFinite(t))) throw new Error('bad --animation or --times');
  return files.map((file) => ({ file, animation, times }));
}

async function main(argv) {
  if (argv.length === 0 || argv.includes('-h') || argv.includes('--help')) {
    console.error('usage: node scripts/pose_three.mjs [--animation A] [--times T1,T2] FILE... | --request REQUEST.json');
    return 2;
  }
  if (argv[0] === '--check') return (await loadThree()) ? 0 : 2;
  let requests;
  try {
    requests = parseArgs(argv);
    if (!Array.isArray(requests)) throw new Error('a request is a JSON array');
  } catch (err) {
    console.error(`pose_three: ${err.message}`);
    return 2;
  }
  const three = await loadThree();
  if (!three) return 2;
  const draco = installDraco(three);
  const out = [];
  for (const r of requests) out.push(await poseFile(three, draco, r));
  draco.dispose();
  process.stdout.write(JSON.stringify(out) + '\n');
  return out.some((e) => e.error !== undefined) ? 1 : 0;
}

main(process.argv.slice(2)).then(
  (status) => { process.exitCode = status; },
  (err) => {
    console.error(`pose_three: ${err && err.stack ? err.stack : err}`);
    process.exitCode = 2;
  },
);
