#!/usr/bin/env node
// Runs the Khronos glTF-Validator (npm package gltf-validator, pinned in package-lock.json)
// on one .glb or .gltf and prints one JSON document on stdout:
//   {"file","numErrors","numWarnings","numInfos","numHints","issues":[{"code","severity","pointer","message"}]}
// where "issues" lists the errors and warnings (severity 0 and 1). Exit status: 0 without
// errors, 1 with errors, 2 when the file cannot be read or the validator fails.
'use strict';
const fs = require('fs');
const path = require('path');
const validator = require('gltf-validator');

const file = process.argv[2];
if (!file) {
  console.error('usage: node validate.js FILE.glb|FILE.gltf');
  process.exit(2);
}

let bytes;
try {
  bytes = new Uint8Array(fs.readFileSync(file));
} catch (e) {
  console.error(`error: ${file}: ${e.message}`);
  process.exit(2);
}

validator.validateBytes(bytes, {
  uri: path.basename(file),
  maxIssues: 0, // report every issue
  externalResourceFunction: (uri) =>
    new Promise((resolve, reject) => {
      fs.readFile(path.resolve(path.dirname(file), decodeURIComponent(uri)), (err, data) =>
        err ? reject(err.toString()) : resolve(new Uint8Array(data)));
    }),
}).then((report) => {
  const issues = report.issues;
  const out = {
    file,
    numErrors: issues.numErrors,
    numWarnings: issues.numWarnings,
    numInfos: issues.numInfos,
    numHints: issues.numHints,
    issues: issues.messages.filter((m) => m.severity <= 1).map((m) => ({
      code: m.code, severity: m.severity, pointer: m.pointer || '', message: m.message,
    })),
  };
  console.log(JSON.stringify(out));
  process.exit(issues.numErrors > 0 ? 1 : 0);
}, (error) => {
  console.error(`error: ${file}: ${error}`);
  process.exit(2);
});
