// Runs the Khronos glTF validator (npm `gltf-validator`, pinned in package.json) on one
// .glb/.gltf file and prints its report as JSON on stdout.
// Usage: node tests/gltf/validate.mjs FILE
// Exit status: 0 when the report has no errors, 1 when it has errors, 2 when the file
// cannot be read or the validator cannot parse it, 3 when the validator is not installed
// (run scripts/setup-node.sh).
import { readFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { basename } from 'node:path';

const require = createRequire(import.meta.url);
let validator;
try {
  validator = require('gltf-validator');
} catch (e) {
  console.error(`gltf-validator is not installed in tests/gltf/node_modules (run scripts/setup-node.sh): ${e.message}`);
  process.exit(3);
}

const file = process.argv[2];
if (!file) {
  console.error('usage: node tests/gltf/validate.mjs FILE');
  process.exit(2);
}

let bytes;
try {
  bytes = new Uint8Array(readFileSync(file));
} catch (e) {
  console.error(`cannot read ${file}: ${e.message}`);
  process.exit(2);
}

try {
  const report = await validator.validateBytes(bytes, {
    uri: basename(file),
    maxIssues: 0, // report every issue
    writeTimestamp: false, // keep the report deterministic
  });
  console.log(JSON.stringify(report, null, 2));
  process.exit(report.issues.numErrors > 0 ? 1 : 0);
} catch (e) {
  console.error(`validator could not process ${file}: ${e}`);
  process.exit(2);
}
