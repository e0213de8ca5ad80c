// The proto/ schema in the browser: message types looked up by their full name
// in the code `npm run gen` generates from proto/rt/*.proto (src/gen), JSON and
// binary conversion, and the rt.limits field options (defaults and ranges).
// Nothing here restates a field: a message moved between .proto files or a new
// setting needs no change in the viewer.
import { create, createRegistry, fromBinary, fromJson, getOption, hasOption, toJson } from "@bufbuild/protobuf";

const modules = import.meta.glob("./gen/rt/*_pb.js", { eager: true });
const files = Object.values(modules).flatMap((module) =>
  Object.entries(module).filter(([name]) => name.startsWith("file_")).map(([, file]) => file));

export const registry = createRegistry(...files);

function lookup(kind, name) {
  const full = `rt.${name}`;
  const desc = kind === "message" ? registry.getMessage(full)
    : kind === "enum" ? registry.getEnum(full) : registry.getExtension(full);
  if (!desc) throw new Error(`proto: no ${kind} ${full} in the generated code (run npm run gen)`);
  return desc;
}

export const schema = (name) => lookup("message", name);
export const enumOf = (name) => lookup("enum", name);
const limitsExtension = lookup("extension", "limits");

/** Enum value name ("DONE") of a number, as the JSON form writes it. */
export function enumName(enumName_, value) {
  return enumOf(enumName_).values.find((v) => v.number === value)?.name ?? String(value);
}

/** The values of an enum a user can choose (all but the _UNSPECIFIED zero). */
export function enumChoices(enumName_) {
  return enumOf(enumName_).values.filter((v) => v.number !== 0);
}

/** rt.Limits of a field ({default, min, max, count, required}), or null. */
export function limitsOf(field) {
  return hasOption(field, limitsExtension) ? getOption(field, limitsExtension) : null;
}

/** A message of type `name` from its JSON form (a server response). */
export function parseJson(name, json) {
  return fromJson(schema(name), json, { ignoreUnknownFields: true });
}

/** The JSON form of a message built from `init` (a request body). */
export function toJsonBody(name, init) {
  const type = schema(name);
  return toJson(type, create(type, init));
}

/** A message of type `name` from its binary form (a WebSocket frame). */
export function parseBinary(name, bytes) {
  return fromBinary(schema(name), bytes instanceof Uint8Array ? bytes : new Uint8Array(bytes));
}

export { create };
