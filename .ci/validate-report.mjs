// Validates JSON reports against schema/report.schema.json with Ajv (JSON Schema 2020-12).
//
// Usage: node .ci/validate-report.mjs FILE.report.json...
// Ajv comes from npm: `npm install --prefix .ci ajv`.
// Prints each file's result and exits 1 if any file does not conform.

import { readFile } from "node:fs/promises";
import { createRequire } from "node:module";
import { join } from "node:path";

const here = new URL(".", import.meta.url).pathname;
const require = createRequire(join(here, "node_modules", "_"));
const Ajv2020 = require("ajv/dist/2020").default;

const files = process.argv.slice(2);
if (files.length === 0) {
  console.error("usage: node .ci/validate-report.mjs FILE.report.json...");
  process.exit(2);
}

const schema = JSON.parse(await readFile(join(here, "..", "schema", "report.schema.json"), "utf8"));
const ajv = new Ajv2020({ allErrors: true, strict: true, strictRequired: false });
const validate = ajv.compile(schema);

let failed = false;
for (const file of files) {
  const report = JSON.parse(await readFile(file, "utf8"));
  if (validate(report)) {
    console.log(`${file}: conforms`);
  } else {
    failed = true;
    console.log(`${file}: does not conform`);
    for (const error of validate.errors) {
      console.log(`  ${error.instancePath || "/"} ${error.message}`);
    }
  }
}
process.exit(failed ? 1 : 0);
