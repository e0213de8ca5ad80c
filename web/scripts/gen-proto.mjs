// Generates the JavaScript message code from proto/rt/*.proto into src/gen
// (gitignored) with Debian's protoc and @bufbuild/protoc-gen-es: the viewer
// never carries a hand-written copy of a message.
import { execFileSync } from "node:child_process";
import { mkdirSync, readdirSync, rmSync } from "node:fs";
import { dirname, join, resolve } from "node:path";
import { fileURLToPath } from "node:url";

const web = resolve(dirname(fileURLToPath(import.meta.url)), "..");
const protoRoot = resolve(web, "..", "proto");
const out = join(web, "src", "gen");
const plugin = join(web, "node_modules", ".bin", "protoc-gen-es");
const protoc = process.env.PROTOC || "protoc";

const files = readdirSync(join(protoRoot, "rt"))
  .filter((name) => name.endsWith(".proto"))
  .sort()
  .map((name) => join(protoRoot, "rt", name));
if (files.length === 0) throw new Error(`gen-proto: no .proto files in ${join(protoRoot, "rt")}`);

rmSync(out, { recursive: true, force: true });
mkdirSync(out, { recursive: true });
try {
  execFileSync(protoc, [
    `-I${protoRoot}`,
    `--plugin=protoc-gen-es=${plugin}`,
    `--es_out=${out}`,
    "--es_opt=target=js,import_extension=js",
    ...files,
  ], { stdio: "inherit" });
} catch (e) {
  if (e.code === "ENOENT") throw new Error(`gen-proto: ${protoc} not found (apt-get install protobuf-compiler)`);
  throw e;
}
console.log(`gen-proto: ${files.length} files from ${protoRoot} into ${out}`);
