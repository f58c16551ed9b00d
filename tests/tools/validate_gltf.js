// Validates glTF/GLB files with the Khronos glTF validator (npm gltf-validator) and prints
// one JSON report summary per file: {"file", "numErrors", "numWarnings", "numInfos", "messages"}.
// Usage: node validate_gltf.js FILE...   (NODE_PATH must reach the gltf-validator package)
"use strict";
const fs = require("fs");
const path = require("path");
const validator = require("gltf-validator");

async function one(file) {
  const bytes = new Uint8Array(fs.readFileSync(file));
  const report = await validator.validateBytes(bytes, {
    uri: path.basename(file),
    maxIssues: 100,
    externalResourceFunction: (uri) =>
      new Promise((resolve, reject) => {
        const p = path.resolve(path.dirname(file), decodeURIComponent(uri));
        fs.readFile(p, (err, data) => (err ? reject(err.toString()) : resolve(new Uint8Array(data))));
      }),
  });
  const i = report.issues;
  return {
    file,
    numErrors: i.numErrors,
    numWarnings: i.numWarnings,
    numInfos: i.numInfos,
    messages: i.messages.map((m) => `${m.severity} ${m.code} ${m.pointer || ""}: ${m.message}`),
    animations: report.info ? report.info.animationCount : null,
  };
}

(async () => {
  const out = [];
  for (const f of process.argv.slice(2)) out.push(await one(f));
  process.stdout.write(JSON.stringify(out) + "\n");
})().catch((e) => {
  process.stderr.write(String(e) + "\n");
  process.exit(3);
});
