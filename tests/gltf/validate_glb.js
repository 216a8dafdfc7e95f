// validate_glb.js: runs the Khronos glTF validator (npm package gltf-validator) on one
// .glb file and prints one JSON line {errors, warnings, infos, messages}. Exit 0 when it
// reports no error, 1 when it reports errors, 2 when it cannot run.
//
//   node tests/gltf/validate_glb.js FILE.glb NODE_MODULES_DIR
'use strict';
const fs = require('fs');
const path = require('path');
if (process.argv.length !== 4) {
  console.error('usage: node validate_glb.js FILE.glb NODE_MODULES_DIR');
  process.exit(2);
}
let validator;
try {
  validator = require(path.resolve(process.argv[3], 'gltf-validator'));
} catch (e) {
  console.error('cannot load gltf-validator from ' + process.argv[3] + ': ' + e.message);
  process.exit(2);
}
let data;
try {
  data = new Uint8Array(fs.readFileSync(process.argv[2]));
} catch (e) {
  console.error('cannot read ' + process.argv[2] + ': ' + e.message);
  process.exit(2);
}
validator.validateBytes(data, {maxIssues: 50}).then((report) => {
  const i = report.issues;
  const worst = i.messages.filter((m) => m.severity === 0).slice(0, 5)
      .map((m) => m.code + ' ' + m.pointer + ': ' + m.message);
  console.log(JSON.stringify({errors: i.numErrors, warnings: i.numWarnings,
                              infos: i.numInfos, messages: worst}));
  process.exit(i.numErrors === 0 ? 0 : 1);
}, (e) => {
  console.error('validator failed: ' + e);
  process.exit(2);
});
