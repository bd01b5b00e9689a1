// The Khronos glTF validator over the files named: one line per file
// ("ok FILE" or "FILE: N errors"), then each error's code, JSON pointer and
// message. Exit 0 when no file has an error (warnings are printed, not
// failed), 1 when one has, 2 when one cannot be read or is not glTF at all
// (every file is still looked at). JavaScript because the
// validator ships only as a JavaScript library (npm gltf-validator).
// Usage: node tools/gltf-validator/validate.mjs FILE.gltf|FILE.glb...
import validator from 'gltf-validator';
import fs from 'node:fs';
import path from 'node:path';

const severity = ['error', 'warning', 'info', 'hint'];
const usage = 'usage: node tools/gltf-validator/validate.mjs FILE.gltf|FILE.glb...';
const files = process.argv.slice(2);
if (files.length === 0 || files.includes('-h') || files.includes('--help')) {
  console.log(usage);
  process.exit(files.length === 0 ? 2 : 0);
}

// A regular file's bytes; anything else (a FIFO would block) is refused.
function readRegular(file) {
  if (!fs.statSync(file).isFile())
    throw new Error('not a regular file');
  return new Uint8Array(fs.readFileSync(file));
}

let status = 0;
const worsen = (s) => { status = Math.max(status, s); };
for (const file of files) {
  let bytes;
  try {
    bytes = readRegular(file);
  } catch (e) {
    console.log(`${file}: cannot read: ${e.message}`);
    worsen(2);
    continue;
  }
  const readResource = (uri) => new Promise((resolve, reject) => {
    try {
      resolve(readRegular(path.join(path.dirname(file), decodeURIComponent(uri))));
    } catch (e) {
      reject(e.message);
    }
  });
  let report;
  try {
    report = await validator.validateBytes(bytes, {uri: file, externalResourceFunction: readResource});
  } catch (e) {  // the validator throws on what is not glTF at all
    console.log(`${file}: not glTF: ${String(e.message ?? e).split('\n')[0]}`);
    worsen(2);
    continue;
  }
  const { numErrors, numWarnings, messages } = report.issues;
  console.log(numErrors ? `${file}: ${numErrors} errors, ${numWarnings} warnings`
                        : `ok ${file} (${numWarnings} warnings)`);
  for (const m of messages)
    if (m.severity <= 1)
      console.log(`  ${severity[m.severity]} ${m.code} ${m.pointer ?? ''}: ${m.message}`);
  if (numErrors)
    worsen(1);
}
process.exit(status);
