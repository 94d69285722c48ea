// Run a wasm32-wasi command under Node's WASI: node run_wasi.mjs prog.wasm [args...]
// (stdout and stderr are the process's; the exit status is the program's).
import { WASI } from 'node:wasi';
import { readFileSync } from 'node:fs';

const [file, ...args] = process.argv.slice(2);
const wasi = new WASI({ version: 'preview1', args: [file, ...args], env: {}, returnOnExit: true });
const { instance } = await WebAssembly.instantiate(readFileSync(file), wasi.getImportObject());
process.exitCode = wasi.start(instance);
