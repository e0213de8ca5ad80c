// Render settings, built from the schema: one labelled number input for every
// numeric field of rt.RenderSettings with its rt.limits default and range, a
// choice for every enum field (its zero value first, the proto default), a
// checkbox for every rt.AuxOutput, and the view's field of view (rt.Camera.fov_y).
// A setting added to render.proto appears here with no change to this file; the
// background's list and message fields have a control of their own.
import { ScalarType } from "@bufbuild/protobuf";
import { BackgroundControl } from "./background-control.js";
import { enumChoices, limitsOf, schema } from "./proto.js";

const INTEGER_SCALARS = new Set([ScalarType.INT32, ScalarType.UINT32, ScalarType.SINT32, ScalarType.FIXED32,
  ScalarType.SFIXED32, ScalarType.INT64, ScalarType.UINT64, ScalarType.SINT64, ScalarType.FIXED64, ScalarType.SFIXED64]);

// Acronyms with vowels, which the rule below cannot tell from words.
const ACRONYMS = new Set(["aces", "oidn"]);

// A field or enum value name in words: "max_depth" is "Max depth"; a word
// without vowels is an acronym ("BVH_COST" is "BVH cost").
export function labelOf(name) {
  const words = name.toLowerCase().split("_")
    .map((w) => (/^[^aeiouy]+$/.test(w) || ACRONYMS.has(w) ? w.toUpperCase() : w));
  const text = words.join(" ");
  return text.charAt(0).toUpperCase() + text.slice(1);
}

function numberInput(id, field, limits) {
  const input = document.createElement("input");
  input.type = "number";
  input.id = id;
  input.name = field.name;
  input.required = true;
  const integer = INTEGER_SCALARS.has(field.scalar);
  input.step = integer ? "1" : "any";
  input.inputMode = integer ? "numeric" : "decimal";
  if (limits?.min !== undefined) input.min = String(limits.min);
  if (limits?.max !== undefined) input.max = String(limits.max);
  if (limits?.default !== undefined) input.value = String(limits.default);
  input.dataset.integer = integer ? "1" : "";
  return input;
}

function enumSelect(id, field) {
  const select = document.createElement("select");
  select.id = id;
  select.name = field.name;
  for (const value of field.enum.values) {
    const option = document.createElement("option");
    option.value = String(value.number);
    option.textContent = labelOf(value.name);
    select.append(option);
  }
  select.value = String(field.enum.values[0].number);
  return select;
}

function describe(limits) {
  if (!limits) return "";
  const parts = [];
  if (limits.min !== undefined && limits.max !== undefined) parts.push(`${limits.min} to ${limits.max}`);
  else if (limits.min !== undefined) parts.push(`at least ${limits.min}`);
  if (limits.default !== undefined) parts.push(`default ${limits.default}`);
  return parts.join(", ");
}

export class SettingsPanel extends EventTarget {
  constructor(form) {
    super();
    this.form = form;
    this.inputs = new Map(); // field localName -> input
    this.outputs = new Map(); // AuxOutput number -> checkbox
    this._build();
  }

  _field(container, field, prefix, text = labelOf(field.name)) {
    const limits = limitsOf(field);
    const id = `${prefix}-${field.name}`;
    const row = document.createElement("div");
    row.className = "field";
    const label = document.createElement("label");
    label.htmlFor = id;
    label.textContent = text;
    const input = field.fieldKind === "enum" ? enumSelect(id, field) : numberInput(id, field, limits);
    const hint = describe(limits);
    if (hint) {
      input.title = hint;
      input.setAttribute("aria-description", hint);
    }
    row.append(label, input);
    container.append(row);
    return input;
  }

  _build() {
    const settings = document.createElement("fieldset");
    settings.innerHTML = "<legend>Render settings</legend>";
    for (const field of schema("RenderSettings").fields) {
      if (field.fieldKind !== "scalar" && field.fieldKind !== "enum") continue;
      const input = this._field(settings, field, "setting");
      this.inputs.set(field.localName, input);
      input.addEventListener("input", () => this._changed(field.localName));
    }
    this.background = new BackgroundControl(settings);
    this.background.addEventListener("change", (e) => this.dispatchEvent(new CustomEvent("background", { detail: e.detail })));
    const fovField = schema("Camera").fields.find((f) => f.name === "fov_y");
    this.fov = this._field(settings, fovField, "camera", "Field of view (vertical, °)");
    this.fov.addEventListener("input", () => {
      if (this.fov.checkValidity()) this.dispatchEvent(new CustomEvent("fov", { detail: Number(this.fov.value) }));
    });
    this.defaultFov = limitsOf(fovField)?.default ?? 45;

    const outputs = document.createElement("fieldset");
    outputs.innerHTML = "<legend>Extra outputs</legend>";
    for (const value of enumChoices("AuxOutput")) {
      const label = document.createElement("label");
      label.className = "check";
      const box = document.createElement("input");
      box.type = "checkbox";
      box.name = "output";
      box.value = value.name;
      box.checked = value.name === "BVH_COST";
      label.append(box, ` ${labelOf(value.name)}`);
      outputs.append(label);
      this.outputs.set(value.number, box);
    }
    const interactiveLabel = document.createElement("label");
    interactiveLabel.className = "check";
    this.interactive = document.createElement("input");
    this.interactive.type = "checkbox";
    this.interactive.checked = true;
    interactiveLabel.append(this.interactive, " Interactive (runs ahead of batch jobs)");
    settings.append(interactiveLabel);

    this.form.prepend(settings, outputs);
  }

  _changed(name) {
    if (name === "width" || name === "height") this.dispatchEvent(new CustomEvent("aspect", { detail: this.aspect }));
    if (name === "lightRig") this.dispatchEvent(new CustomEvent("lightRig", { detail: this.rigOn }));
  }

  /** Whether the default light rig lights a scene without lights (rt.LightRig). */
  get rigOn() {
    return enumChoices("LightRig").find((v) => v.name === "NO_RIG")?.number !== Number(this.inputs.get("lightRig")?.value);
  }

  get aspect() {
    const w = Number(this.inputs.get("width")?.value);
    const h = Number(this.inputs.get("height")?.value);
    return w > 0 && h > 0 ? w / h : 4 / 3;
  }

  /** Checks every input; reports the first problem in the browser's words. */
  validate() {
    for (const input of [...this.inputs.values(), this.fov]) {
      if (!input.checkValidity()) {
        input.reportValidity();
        return false;
      }
    }
    return true;
  }

  /** rt.RenderSettings init: every field as entered. */
  settings() {
    const out = {};
    for (const [name, input] of this.inputs) out[name] = Number(input.value);
    return { ...out, ...this.background.settings() };
  }

  /** The chosen rt.AuxOutput numbers. */
  outputValues() {
    return [...this.outputs].filter(([, box]) => box.checked).map(([value]) => value);
  }

  /** Shows a job's settings (a reloaded /jobs/<id>). */
  show(settings, outputs, interactive) {
    for (const [name, input] of this.inputs) {
      if (settings[name] !== undefined) input.value = String(settings[name]);
    }
    for (const [value, box] of this.outputs) box.checked = outputs.includes(value);
    this.background.show(settings);
    this.interactive.checked = interactive;
    this.dispatchEvent(new CustomEvent("aspect", { detail: this.aspect }));
    this.dispatchEvent(new CustomEvent("lightRig", { detail: this.rigOn }));
  }

  showFov(fov) {
    if (document.activeElement !== this.fov) this.fov.value = String(Math.round(fov * 1000) / 1000);
  }
}
