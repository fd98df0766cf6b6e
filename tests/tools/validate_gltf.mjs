// The Khronos glTF validator (npm gltf-validator, pinned in package.json) on one .glb / .gltf:
//   node validate_gltf.mjs FILE
// Prints the report's summary and every issue (severity, code, JSON pointer, message); exits 1 if
// the validator reports any error, 2 on bad usage or an unreadable file. It must run from the
// folder `npm ci` installed node_modules into (the build copies it to <build>/gltf-tools).
import fs from 'node:fs';
import path from 'node:path';
import validator from 'gltf-validator';

const SEVERITY = ['error', 'warning', 'info', 'hint'];

async function main() {
  if (process.argv.length !== 3) {
    console.error('usage: node validate_gltf.mjs FILE');
    return 2;
  }
  const file = process.argv[2];
  let bytes;
  try {
    bytes = new Uint8Array(fs.readFileSync(file));
  } catch (e) {
    console.error(`validate_gltf: cannot read ${file}: ${e.message}`);
    return 2;
  }
  const report = await validator.validateBytes(bytes, {
    uri: path.basename(file),
    maxIssues: 0,           // report everything
    writeTimestamp: false,  // reproducible output
    // A .glb carries its buffer; any external reference is reported as unloadable.
    externalResourceFunction: (uri) => Promise.reject(new Error(`external resource '${uri}' not expected`)),
  });
  const i = report.issues;
  console.log(`glTF validator ${report.validatorVersion} on ${report.uri}: ${i.numErrors} errors, ` +
              `${i.numWarnings} warnings, ${i.numInfos} infos, ${i.numHints} hints`);
  const info = report.info || {};
  console.log(`  version ${info.version}, generator ${info.generator}, ${info.animationCount} animations, ` +
              `${info.drawCallCount} draw calls, ${info.totalVertexCount} vertices, ${info.totalTriangleCount} triangles`);
  for (const m of i.messages) {
    console.log(`  ${SEVERITY[m.severity] ?? m.severity} ${m.code} ${m.pointer ?? ''}: ${m.message}`);
  }
  return i.numErrors > 0 ? 1 : 0;
}

main().then((code) => process.exit(code), (e) => {
  console.error(`validate_gltf: ${e && e.stack ? e.stack : e}`);
  process.exit(2);
});
