#!/usr/bin/env node
// SPDX-License-Identifier: MIT
//
// Validates glTF 2.0 files (.gltf or .glb) with the Khronos glTF-Validator.
//
//   node scripts/validate_gltf.mjs FILE [FILE...]
//
// The validator is the npm package `gltf-validator`, installed by scripts/deps.sh into
// build/tools/node_modules/gltf-validator. Set DEEPCUT_VALIDATOR_DIR to use another copy
// (the directory that holds the package's package.json).
//
// Prints one summary line per file, then each error (at most 20 per file).
// Exit status: 0 no file has errors, 1 some file has errors, 2 a file could not be read or
// the validator is missing.

import fs from 'node:fs';
import path from 'node:path';
import { createRequire } from 'node:module';
import { fileURLToPath } from 'node:url';

const kMaxErrorLines = 20;
const kSeverityError = 0;  // validator severities: 0 error, 1 warning, 2 info, 3 hint

const scriptDir = path.dirname(fileURLToPath(import.meta.url));
const repoRoot = path.resolve(scriptDir, '..');

function loadValidator() {
  const dir = process.env.DEEPCUT_VALIDATOR_DIR
    ? path.resolve(process.env.DEEPCUT_VALIDATOR_DIR)
    : path.join(repoRoot, 'build', 'tools', 'node_modules', 'gltf-validator');
  if (!fs.existsSync(path.join(dir, 'package.json'))) {
    console.error(`validate_gltf: glTF validator not found in ${dir}`);
    console.error('validate_gltf: install it with: bash scripts/deps.sh (or set DEEPCUT_VALIDATOR_DIR)');
    return null;
  }
  try {
    // The package is CommonJS (index.js); load it by path so no module resolution is involved.
    const require = createRequire(path.join(dir, 'package.json'));
    const validator = require(dir);
    if (typeof validator.validateBytes !== 'function') {
      throw new Error('module has no validateBytes()');
    }
    return validator;
  } catch (err) {
    console.error(`validate_gltf: cannot load the glTF validator from ${dir}: ${err.message}`);
    return null;
  }
}

// Returns true when `child` is `parent` itself or lies inside it.
function isInside(parent, child) {
  const rel = path.relative(parent, child);
  return rel === '' || (!rel.startsWith('..') && !path.isAbsolute(rel));
}

// Loads resources referenced by a .gltf, relative to its folder, refusing anything outside it.
// data: URIs never reach this function: the validator decodes them itself.
function makeResourceLoader(file) {
  const baseDir = fs.realpathSync(path.dirname(path.resolve(file)));
  return async (uri) => {
    if (/^[a-zA-Z][a-zA-Z0-9+.-]*:/.test(uri)) {
      throw new Error(`refusing non-relative URI ${uri}`);
    }
    let decoded;
    try {
      decoded = decodeURIComponent(uri);
    } catch {
      throw new Error(`malformed URI ${uri}`);
    }
    const target = path.resolve(baseDir, decoded);
    if (!isInside(baseDir, target)) {
      throw new Error(`refusing URI ${uri}: it points outside ${baseDir}`);
    }
    const real = await fs.promises.realpath(target);  // also catches symlinks that escape
    if (!isInside(baseDir, real)) {
      throw new Error(`refusing URI ${uri}: it resolves outside ${baseDir}`);
    }
    return new Uint8Array(await fs.promises.readFile(real));
  };
}

// Validates one file; returns 0 (no errors), 1 (errors) or 2 (unreadable).
async function validateFile(validator, file) {
  let bytes;
  try {
    bytes = new Uint8Array(fs.readFileSync(file));
  } catch (err) {
    console.log(`${file}: cannot read: ${err.message}`);
    return 2;
  }
  const options = {
    uri: path.basename(file),
    maxIssues: 0,  // unlimited, so the counts are exact
    writeTimestamp: false,
  };
  const ext = path.extname(file).toLowerCase();
  if (ext === '.glb') options.format = 'glb';
  if (ext === '.gltf') {
    options.format = 'gltf';
    options.externalResourceFunction = makeResourceLoader(file);
  }

  let report;
  try {
    report = await validator.validateBytes(bytes, options);
  } catch (err) {
    // A rejection means the bytes are not recognisable glTF/GLB at all: the file is invalid.
    console.log(`${file}: 1 errors, 0 warnings, 0 infos`);
    console.log(`  error VALIDATOR_REJECTED: ${String(err)} (/)`);
    return 1;
  }

  const issues = report.issues || {};
  const numErrors = issues.numErrors || 0;
  console.log(`${file}: ${numErrors} errors, ${issues.numWarnings || 0} warnings, ${issues.numInfos || 0} infos`);
  const errors = (issues.messages || []).filter((m) => m.severity === kSeverityError);
  for (const m of errors.slice(0, kMaxErrorLines)) {
    const where = m.pointer !== undefined ? m.pointer : m.offset !== undefined ? `byte ${m.offset}` : '/';
    console.log(`  error ${m.code}: ${m.message} (${where})`);
  }
  if (errors.length > kMaxErrorLines) {
    console.log(`  ... and ${errors.length - kMaxErrorLines} more errors`);
  }
  return numErrors > 0 ? 1 : 0;
}

async function main(argv) {
  if (argv.length === 0 || argv.includes('-h') || argv.includes('--help')) {
    console.error('usage: node scripts/validate_gltf.mjs FILE [FILE...]');
    return 2;
  }
  const validator = loadValidator();
  if (!validator) return 2;
  let status = 0;
  for (const file of argv) {
    status = Math.max(status, await validateFile(validator, file));
  }
  return status;
}

main(process.argv.slice(2)).then(
  (status) => { process.exitCode = status; },
  (err) => {
    console.error(`validate_gltf: ${err && err.stack ? err.stack : err}`);
    process.exitCode = 2;
  },
);
