// Times delaunator on points from a binary file (little-endian float64 x0 y0 x1 y1 ...).
// Usage: node run.mjs POINTS.f64 WARMUP REPETITIONS
// Prints one JSON object: versions, triangle count, and the time of each repetition in ms.
// Only `new Delaunator(coords)` is timed, in this process, after the warm-up runs have let the
// JIT compile it; reading the file is not timed.
import { readFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import Delaunator from 'delaunator';

const [file, warmupArg, repsArg] = process.argv.slice(2);
const warmup = Number(warmupArg ?? 1);
const reps = Number(repsArg ?? 5);

const bytes = readFileSync(file);
// A Float64Array view needs an 8-byte aligned offset; copy when Node's buffer pool gave us
// an unaligned one.
const coords = bytes.byteOffset % 8 === 0
  ? new Float64Array(bytes.buffer, bytes.byteOffset, bytes.byteLength / 8)
  : new Float64Array(new Uint8Array(bytes).buffer);

let triangles = 0;
const run = () => {
  const start = process.hrtime.bigint();
  const d = new Delaunator(coords);
  const end = process.hrtime.bigint();
  triangles = d.triangles.length / 3;
  return Number(end - start) / 1e6;
};

for (let i = 0; i < warmup; ++i) run();
const samples = [];
for (let i = 0; i < reps; ++i) samples.push(run());

const require = createRequire(import.meta.url);
const version = require('delaunator/package.json').version;
console.log(JSON.stringify({ delaunator: version, node: process.versions.node, triangles, samples_ms: samples }));
