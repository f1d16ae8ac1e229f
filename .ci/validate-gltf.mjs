// Validates binary glTF files with the Khronos glTF validator.
//
// Usage: node .ci/validate-gltf.mjs FILE.glb...
// The validator comes from npm: `npm install --prefix .ci gltf-validator`, or set
// GLTF_VALIDATOR_PREFIX to the prefix it was installed under.
// Prints each file's issue summary and exits 1 if any file has errors.

import { readFile } from "node:fs/promises";
import { createRequire } from "node:module";
import { join, resolve } from "node:path";

const prefix = process.env.GLTF_VALIDATOR_PREFIX ?? new URL(".", import.meta.url).pathname;
const require = createRequire(join(resolve(prefix), "node_modules", "_"));
const validator = require("gltf-validator");

const files = process.argv.slice(2);
if (files.length === 0) {
  console.error("usage: node .ci/validate-gltf.mjs FILE.glb...");
  process.exit(2);
}

let failed = false;
for (const file of files) {
  const bytes = await readFile(file);
  const report = await validator.validateBytes(new Uint8Array(bytes), {
    maxIssues: 0,
    writeTimestamp: false,
  });
  const { numErrors, numWarnings, numInfos, numHints, messages } = report.issues;
  console.log(
    `${file}: ${numErrors} errors, ${numWarnings} warnings, ${numInfos} infos, ${numHints} hints`,
  );
  const severities = ["error", "warning", "info", "hint"];
  for (const m of messages) {
    console.log(`  ${severities[m.severity] ?? m.severity} ${m.code} ${m.pointer ?? ""}: ${m.message}`);
  }
  if (numErrors > 0) failed = true;
}
process.exit(failed ? 1 : 0);
