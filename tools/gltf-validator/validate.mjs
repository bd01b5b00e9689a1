// The Khronos glTF validator over the files named: one line per file
// ("ok FILE" or "FILE: N errors"), then each error's code, JSON pointer and
// message. Exit 0 when no file has an error (warnings are printed, not
// failed), 1 when one has, 2 when one cannot be read. JavaScript because the
// validator ships only as a JavaScript library (npm gltf-validator).
// Usage: node tools/gltf-validator/validate.mjs FILE.gltf|FILE.glb...
import validator from 'gltf-validator';
import fs from 'node:fs';
import path from 'node:path';

const severity = ['error', 'warning', 'info', 'hint'];
let status = 0;
for (const file of process.argv.slice(2)) {
  let bytes;
  try {
    bytes = new Uint8Array(fs.readFileSync(file));
  } catch (e) {
    console.log(`${file}: cannot read: ${e.message}`);
    status = 2;
    continue;
  }
  const readResource = (uri) => new Promise((resolve, reject) => {
    try {
      resolve(new Uint8Array(fs.readFileSync(path.join(path.dirname(file), decodeURIComponent(uri)))));
    } catch (e) {
      reject(e.message);
    }
  });
  const report = await validator.validateBytes(bytes, {uri: file, externalResourceFunction: readResource});
  const { numErrors, numWarnings, messages } = report.issues;
  console.log(numErrors ? `${file}: ${numErrors} errors, ${numWarnings} warnings`
                        : `ok ${file} (${numWarnings} warnings)`);
  for (const m of messages)
    if (m.severity <= 1)
      console.log(`  ${severity[m.severity]} ${m.code} ${m.pointer ?? ''}: ${m.message}`);
  if (numErrors && status === 0)
    status = 1;
}
process.exit(status);
