// Loads ballast's binary glTF files with three.js's GLTFLoader, as a web viewer does, and checks
// that they read right there: every pose a visible group in the default scene, the body
// translucent so the capsules and balls show, every mark a mesh (no line primitives), the pose's
// flat extras scalars, a standing pose's support polygon and body on the ground at height 0, and
// no two poses overlapping.
//
// Usage: node tests/viewer/check.mjs FILE.glb...  (three.js from `npm ci` in tests/viewer)
// Prints one line per file and exits 1 when a check fails.

import { readFile } from "node:fs/promises";
import { Box3 } from "three";
import { GLTFLoader } from "three/addons/loaders/GLTFLoader.js";

const files = process.argv.slice(2);
if (files.length === 0) {
  console.error("usage: node tests/viewer/check.mjs FILE.glb...");
  process.exit(2);
}

function load(bytes) {
  const buffer = bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength);
  return new Promise((resolve, reject) => new GLTFLoader().parse(buffer, "", resolve, reject));
}

function isScalar(value) {
  return ["number", "boolean", "string"].includes(typeof value);
}

// The problems found in one loaded file.
function check(gltf) {
  const problems = [];
  const scene = gltf.scene;
  scene.updateMatrixWorld(true);
  // three.js turns spaces in names into underscores.
  if (scene.name !== "all_poses") problems.push(`the default scene is "${scene.name}"`);
  const groups = scene.children;
  if (groups.length === 0) problems.push("the default scene is empty");
  if (gltf.scenes.length !== groups.length + 1) {
    problems.push(`${gltf.scenes.length} scenes for ${groups.length} poses`);
  }

  const boxes = [];
  for (const group of groups) {
    const name = group.userData.name;
    const extras = group.userData;
    if (!group.visible) problems.push(`pose ${name} is hidden`);
    if (extras.pose !== name) problems.push(`group ${name} carries the extras of ${extras.pose}`);
    const flat = Object.keys(extras).filter((key) => key.startsWith("goal."));
    if (flat.length === 0) problems.push(`pose ${name} has no goal.* extras`);
    for (const key of [...flat, "mass_g"]) {
      if (!isScalar(extras[key])) problems.push(`extra ${key} of ${name} is not a scalar`);
    }

    const seen = { component: 0, capsule: 0, steel: 0, gravity: 0, "support polygon": 0 };
    const ground = new Box3();
    const body = new Box3();
    group.traverse((object) => {
      if (object.isLine || object.isLineSegments || object.isLineLoop || object.isPoints) {
        problems.push(`${object.userData.name} is drawn as lines or points`);
      }
      if (!object.isMesh) return;
      if (!object.visible) problems.push(`${object.userData.name} is hidden`);
      const material = object.material;
      if (material.name in seen) seen[material.name] += 1;
      if (["component", "capsule"].includes(material.name)) {
        if (!(material.transparent && material.opacity < 1)) {
          problems.push(`${object.userData.name} (${material.name}) is opaque`);
        }
      }
      if (material.name === "support polygon") ground.expandByObject(object);
      if (material.name === "component") body.expandByObject(object, true);
    });
    for (const kind of ["component", "gravity"]) {
      if (seen[kind] === 0) problems.push(`pose ${name} shows no ${kind} mesh`);
    }
    if (gltf.parser.json.nodes.some((node) => node.name.endsWith("/ball")) && seen.steel === 0) {
      problems.push(`pose ${name} shows no ball`);
    }
    // A pose drawing a support polygon stands: the polygon's tubes lie on the ground, centred
    // on height 0.
    if (seen["support polygon"] > 0) {
      const middle = (ground.min.y + ground.max.y) / 2;
      const size = ground.max.distanceTo(ground.min);
      if (Math.abs(middle) > 1e-3 * size) {
        problems.push(`pose ${name} has its support polygon at height ${middle} m, not 0`);
      }
      // The body stands on that ground: its lowest point at height 0, not through the floor
      // (the pose drawn as it settles, where its support and centre of mass are).
      const depth = body.max.distanceTo(body.min);
      if (Math.abs(body.min.y) > 1e-3 * depth) {
        problems.push(`pose ${name} has its body's lowest point at height ${body.min.y} m, not 0`);
      }
    }
    boxes.push([name, new Box3().setFromObject(group)]);
  }
  for (let i = 0; i < boxes.length; i++) {
    for (let j = i + 1; j < boxes.length; j++) {
      if (boxes[i][1].intersectsBox(boxes[j][1])) {
        problems.push(`poses ${boxes[i][0]} and ${boxes[j][0]} overlap`);
      }
    }
  }
  return problems;
}

let failed = false;
for (const file of files) {
  const gltf = await load(await readFile(file));
  const problems = check(gltf);
  console.log(`${file}: ${gltf.scene.children.length} poses, ${problems.length} problems`);
  for (const problem of problems) console.log(`  ${problem}`);
  failed ||= problems.length > 0;
}
process.exit(failed ? 1 : 0);
