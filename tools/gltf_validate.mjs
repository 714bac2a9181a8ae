// Validate binary glTF files with the Khronos glTF-Validator (npm package gltf-validator).
//
// Usage: node gltf_validate.mjs NODE_PREFIX FILE.glb...
//
// NODE_PREFIX is a directory whose node_modules holds gltf-validator (made by
// `npm install --prefix NODE_PREFIX gltf-validator@2.0.0-dev.3.10`, as
// crates/hull/tests/io/exports.rs does). Prints one JSON object {"ok", "validator", "files":
// [{"file", "issues": {numErrors, numWarnings, numInfos, numHints, messages}}]}; exit status 0
// when no file has an error or a warning, 1 otherwise, 2 if the validator cannot be loaded.
import { createRequire } from 'module';
import { readFileSync } from 'fs';
import path from 'path';

const [prefix, ...files] = process.argv.slice(2);
let validator;
try {
  validator = createRequire(path.resolve(prefix) + '/')('gltf-validator');
} catch (e) {
  console.log(JSON.stringify({ ok: false, error: `cannot load gltf-validator from ${prefix}: ${e}` }));
  process.exit(2);
}
const out = [];
let ok = true;
for (const file of files) {
  const report = await validator.validateBytes(new Uint8Array(readFileSync(file)));
  const issues = report.issues;
  ok = ok && issues.numErrors === 0 && issues.numWarnings === 0;
  out.push({ file, issues });
}
console.log(JSON.stringify({ ok, validator: validator.version(), files: out }));
process.exit(ok ? 0 : 1);
