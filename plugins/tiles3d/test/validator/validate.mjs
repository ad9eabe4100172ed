// SPDX-License-Identifier: Apache-2.0
// Runs Khronos' glTF-Validator on every GLB given (files or folders, searched recursively):
// prints each file's errors and warnings (code and message) and a summary; exits 1 if any file
// has an error. Usage: node validate.mjs <node_modules dir> <path>...
import { createRequire } from 'module';
import fs from 'fs';
import path from 'path';

const require = createRequire(path.join(path.resolve(process.argv[2]), 'x.js'));
const validator = require('gltf-validator');

function glbs(p) {
    const st = fs.statSync(p);
    if (st.isFile()) return p.endsWith('.glb') ? [p] : [];
    return fs.readdirSync(p).sort().flatMap((e) => glbs(path.join(p, e)));
}

const files = process.argv.slice(3).flatMap(glbs);
let errors = 0;
const warnings = new Map();
for (const file of files) {
    const report = await validator.validateBytes(new Uint8Array(fs.readFileSync(file)), {
        uri: file,
        maxIssues: 0,
    });
    const issues = report.issues;
    errors += issues.numErrors;
    for (const m of issues.messages) {
        if (m.severity === 0) console.log(`${file}: ERROR ${m.code}: ${m.message} (${m.pointer || ''})`);
        if (m.severity === 1) {
            const key = `${m.code}: ${m.message}`;
            warnings.set(key, (warnings.get(key) || 0) + 1);
        }
    }
}
for (const [w, n] of warnings) console.log(`WARNING x${n} ${w}`);
console.log(`gltf-validator ${validator.version()}: ${files.length} GLB files, ${errors} errors, ` +
            `${[...warnings.values()].reduce((a, b) => a + b, 0)} warnings`);
process.exit(files.length > 0 && errors === 0 ? 0 : 1);
