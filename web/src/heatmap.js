// What the image panel shows: the streamed colour image, or one of a finished
// job's auxiliary outputs; "BVH cost" is the server's heat map of BVH nodes
// visited per pixel, where rays are expensive.
import { heatRampUrl, jobImageUrl } from "./api.js";
import { layerNames } from "./job-layers.js";
import { enumChoices } from "./proto.js";
import { labelOf } from "./settings-panel.js";

export class ImageLayers extends EventTarget {
  constructor(group, image, legend) {
    super();
    this.group = group;
    this.image = image; // <img> over the tile canvas
    this.legend = legend;
    this.buttons = new Map();
    this.job = null;
    this.current = "image";
    const choices = [["image", "Image"], ...enumChoices("AuxOutput").map((v) => [v.name.toLowerCase(), labelOf(v.name)])];
    for (const [name, label] of choices) {
      const button = document.createElement("button");
      button.type = "button";
      button.textContent = label;
      button.dataset.layer = name;
      button.setAttribute("aria-pressed", String(name === "image"));
      button.addEventListener("click", () => this.select(name));
      this.buttons.set(name, button);
      group.append(button);
    }
    this.image.addEventListener("error", () => {
      if (this.current !== "image") this.dispatchEvent(new CustomEvent("error", { detail: `the ${this.current} image could not be loaded` }));
    });
    this.setJob(null);
  }

  /** Which layers a job offers: colour always, auxiliary ones once it is done. */
  setJob(job, done = false) {
    this.job = job;
    const outputs = new Set(job ? layerNames(job) : []);
    for (const [name, button] of this.buttons) {
      const available = name === "image" ? !!job : done && outputs.has(name);
      button.disabled = !available;
      button.title = available ? "" : name === "image" ? "no job yet" : done ? "not asked for in this job's outputs" : "available when the job is done";
    }
    if (this.current !== "image" && this.buttons.get(this.current).disabled) this.select("image");
    else if (this.current !== "image") this.select(this.current);
  }

  select(name) {
    this.current = name;
    for (const [n, button] of this.buttons) button.setAttribute("aria-pressed", String(n === name));
    const aux = name !== "image" && this.job;
    this.image.hidden = !aux;
    if (aux) {
      const src = jobImageUrl(this.job.id, name, "png");
      if (this.image.getAttribute("src") !== src) this.image.src = src;
      this.image.alt = `${name.replace("_", " ")} output of job ${this.job.id}`;
    }
    this.legend.hidden = name !== "bvh_cost";
    const ramp = this.legend.querySelector("img.ramp");
    if (!this.legend.hidden && !ramp.getAttribute("src")) ramp.src = heatRampUrl();
    this.dispatchEvent(new CustomEvent("layer", { detail: name }));
  }
}
