#!/usr/bin/env node
// Loads one .glb or .gltf with three.js r187 (GLTFLoader, in Node) and Babylon.js 9
// (NullEngine, the glTF loader of @babylonjs/loaders), both with meshoptimizer's decoder for
// EXT_meshopt_compression (the one three.js ships; Babylon's default fetches it from a CDN,
// so it gets the same one), plays animation ANIMATION at SECONDS in each and prints one JSON
// document on stdout:
//   {"file", "three": {"animations": [names], "duration", "vertices", "rotations": {node: [x, y, z, w]}},
//            "babylon": {"animations": [names], "vertices", "rotations": {node: [x, y, z, w]}}}
// where "vertices" counts the vertices of the meshes it shows (three.js: the scene's; Babylon:
// every mesh it made) and "rotations" are the local rotations of every node the animation rotates, after
// playing it to SECONDS. Exit status: 0 when both loaded, 1 when one failed (its error on
// stderr), 2 for bad arguments. Versions are pinned by package-lock.json (`npm ci`).
import fs from 'node:fs';
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { MeshoptDecoder } from 'three/addons/libs/meshopt_decoder.module.js';
import { NullEngine, Scene, LoadAssetContainerAsync, Logger } from '@babylonjs/core';
import { MeshoptCompression } from '@babylonjs/core/Meshes/Compression/meshoptCompression.js';
import '@babylonjs/loaders/glTF/2.0/index.js';

// three.js reads a .gltf's data URI with fetch() and reports progress with ProgressEvent,
// which Node lacks
if (typeof globalThis.ProgressEvent === 'undefined') {
  globalThis.ProgressEvent = class extends Event {
    constructor(type, init = {}) {
      super(type);
      Object.assign(this, init);
    }
  };
}

const [file, animationArg = '0', secondsArg = '0'] = process.argv.slice(2);
if (!file) {
  console.error('usage: node play.mjs FILE.glb|FILE.gltf [ANIMATION] [SECONDS]');
  process.exit(2);
}
const animation = Number(animationArg);
const seconds = Number(secondsArg);
const bytes = fs.readFileSync(file);
const arrayBuffer = bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength);
const out = { file };
let failed = false;

async function three() {
  const loader = new GLTFLoader();
  loader.setMeshoptDecoder(MeshoptDecoder);
  const gltf = await loader.parseAsync(arrayBuffer, '');
  const clip = gltf.animations[animation];
  let vertices = 0;
  gltf.scene.traverse((o) => { if (o.isMesh) vertices += o.geometry.attributes.position.count; });
  const result = { animations: gltf.animations.map((a) => a.name), duration: clip ? clip.duration : 0, vertices, rotations: {} };
  if (clip) {
    const mixer = new THREE.AnimationMixer(gltf.scene);
    mixer.clipAction(clip).play();
    mixer.setTime(seconds);
    for (const track of clip.tracks) {
      if (!track.name.endsWith('.quaternion')) continue;
      const name = track.name.slice(0, -'.quaternion'.length);
      const node = gltf.scene.getObjectByName(name);
      if (node) result.rotations[name] = node.quaternion.toArray();
    }
  }
  return result;
}

async function babylon() {
  Logger.LogLevels = Logger.ErrorLogLevel;
  await MeshoptDecoder.ready;
  // the decoder three.js ships, in place of the CDN script Babylon would load
  MeshoptCompression._Default = {
    decodeGltfBufferAsync: (source, count, stride, mode, filter) => {
      const target = new Uint8Array(count * stride);
      MeshoptDecoder.decodeGltfBuffer(target, count, stride, source, mode, filter);
      return Promise.resolve(target);
    },
    dispose() {},
  };
  const engine = new NullEngine();
  const scene = new Scene(engine);
  // a .glb as bytes; a .gltf (text, which Babylon does not take as bytes) as a data URL
  const text = file.toLowerCase().endsWith('.gltf');
  const source = text ? `data:model/gltf+json;base64,${bytes.toString('base64')}` : new Uint8Array(arrayBuffer);
  const container = await LoadAssetContainerAsync(source, scene, { pluginExtension: text ? '.gltf' : '.glb' });
  container.addAllToScene();
  const groups = container.animationGroups;
  const vertices = container.meshes.reduce((n, m) => n + (m.getTotalVertices ? m.getTotalVertices() : 0), 0);
  const result = { animations: groups.map((g) => g.name), vertices, rotations: {} };
  const group = groups[animation];
  if (group) {
    for (const g of groups) g.stop();
    group.start(false, 1.0);
    group.pause();
    group.goToFrame(seconds * 60); // the glTF loader keys animations at 60 frames a second
    for (const { target, animation: a } of group.targetedAnimations) {
      if (a.targetProperty !== 'rotationQuaternion' || !target.rotationQuaternion) continue;
      const q = target.rotationQuaternion;
      result.rotations[target.name] = [q.x, q.y, q.z, q.w];
    }
  }
  engine.dispose();
  return result;
}

for (const [name, load] of [['three', three], ['babylon', babylon]]) {
  try {
    out[name] = await load();
  } catch (error) {
    console.error(`error: ${file}: ${name}: ${error && error.stack ? error.stack : error}`);
    failed = true;
  }
}
console.log(JSON.stringify(out));
process.exit(failed ? 1 : 0);
