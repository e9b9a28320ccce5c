// Runs the Khronos glTF validator on a .gltf/.glb (with its external .bin and images) and prints the report.
// Exit 0: no errors; 1: the asset has errors; 2: usage or the validator module is missing.
//   npm install -g gltf-validator
//   NODE_PATH=$(npm root -g) node scripts/validate-gltf.mjs out/relief.gltf
import { createRequire } from 'module';
import { readFile } from 'fs/promises';
import path from 'path';

const require = createRequire(import.meta.url);
let validator;
try {
    validator = require('gltf-validator');
} catch (e) {
    console.error('validate-gltf: the gltf-validator module is missing (npm install -g gltf-validator; ' +
                  'NODE_PATH=$(npm root -g))');
    process.exit(2);
}
const file = process.argv[2];
if (!file) {
    console.error('usage: node scripts/validate-gltf.mjs ASSET.gltf');
    process.exit(2);
}
const bytes = new Uint8Array(await readFile(file));
const report = await validator.validateBytes(bytes, {
    uri: path.basename(file),
    maxIssues: 0,
    externalResourceFunction: (uri) =>
        readFile(path.resolve(path.dirname(file), decodeURIComponent(uri))).then((b) => new Uint8Array(b)),
});
console.log(JSON.stringify(report, null, 2));
const n = report.issues;
console.error(`${file}: ${n.numErrors} errors, ${n.numWarnings} warnings, ${n.numInfos} infos, ${n.numHints} hints`);
process.exit(n.numErrors > 0 ? 1 : 0);
