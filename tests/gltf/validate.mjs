// Runs the Khronos glTF validator on .glb files: prints each file's counts and messages, and
// exits 1 if any file has an error, 77 (skipped, for CTest) if the validator is not installed
// and $CI is not set (bash scripts/deps.sh installs it here).
import { readFile } from 'node:fs/promises';
import { createRequire } from 'node:module';

const require = createRequire(import.meta.url);
let validator;
try {
  validator = require('gltf-validator');
} catch {
  console.error('validate: gltf-validator is not installed in tests/gltf; run bash scripts/deps.sh');
  process.exit(process.env.CI ? 1 : 77);
}

let failed = false;
for (const file of process.argv.slice(2)) {
  const report = await validator.validateBytes(new Uint8Array(await readFile(file)), {
    maxIssues: 100,
  });
  const { numErrors, numWarnings, numInfos, numHints } = report.issues;
  console.log(`${file}: glTF ${report.info?.version}, ${numErrors} errors, ${numWarnings} ` +
              `warnings, ${numInfos} infos, ${numHints} hints (validator ${report.validatorVersion})`);
  const info = report.info ?? {};
  console.log(`  ${info.drawCallCount} draw calls, ${info.totalVertexCount} vertices, ` +
              `${info.animationCount} animations, ${info.maxAttributes} attributes at most`);
  for (const m of report.issues.messages) {
    console.log(`  [${['error', 'warning', 'info', 'hint'][m.severity]}] ${m.code} at ` +
                `${m.pointer ?? m.offset ?? '?'}: ${m.message}`);
  }
  if (numErrors > 0) failed = true;
}
process.exit(failed ? 1 : 0);
