// Validates GLB files with the Khronos glTF validator (the npm package
// `gltf-validator`, pinned in package.json): `node validate-glb.mjs A.glb …`
// prints one line per file (triangles, warnings) and exits 1 listing the
// errors of any file that has some. scripts/test-studio runs it on every
// building example sampled with no flags. Files after `--textured` must
// also embed textures, have texture coordinates and give no warning.
import fs from 'node:fs';
import path from 'node:path';
import validator from 'gltf-validator';

let failed = 0;
let textured = false;
for (const file of process.argv.slice(2)) {
  if (file === '--textured') {
    textured = true;
    continue;
  }
  const bytes = fs.readFileSync(file);
  const report = await validator.validateBytes(new Uint8Array(bytes), { uri: path.basename(file), format: 'glb', maxIssues: 50 });
  const { numErrors, numWarnings } = report.issues;
  console.log(`${path.basename(file)}: ${bytes.length} bytes, ${report.info?.totalTriangleCount ?? '?'} triangles, ${numErrors} errors, ${numWarnings} warnings`);
  if (textured && !(report.info?.hasTextures && report.info?.maxUVs >= 1 && numWarnings === 0)) {
    failed++;
    console.log(`  expected textures, texture coordinates and no warning: ${JSON.stringify(report.info)}`);
  }
  if (numErrors > 0) {
    failed++;
    for (const m of report.issues.messages.filter((m) => m.severity === 0)) {
      console.log(`  ${m.code} ${m.pointer || ''}: ${m.message}`);
    }
  }
}
process.exit(failed > 0 ? 1 : 0);
