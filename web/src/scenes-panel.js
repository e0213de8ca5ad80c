// Scenes: upload by drag-and-drop or file picker with progress and the
// server's reason when it refuses a file; the list of stored scenes to pick
// from, each with a delete button.
import { deleteScene, listScenes, uploadScene } from "./api.js";
import { formatBytes } from "./format.js";

const ACCEPT = [".glb", ".gltf", ".obj", ".zip"];

export class ScenesPanel extends EventTarget {
  constructor(root) {
    super();
    this.drop = root.querySelector("#drop-zone");
    this.input = root.querySelector("#scene-file");
    this.progress = root.querySelector("#upload-progress");
    this.status = root.querySelector("#upload-status");
    this.list = root.querySelector("#scene-list");
    this.selected = null;
    this.scenes = [];
    this.sharedReadOnly = false; // set once the server is known to have named users
    this.input.accept = ACCEPT.join(",");
    this.input.addEventListener("change", () => {
      if (this.input.files.length) this.upload(this.input.files[0]);
      this.input.value = "";
    });
    for (const type of ["dragenter", "dragover"]) {
      this.drop.addEventListener(type, (e) => {
        e.preventDefault();
        this.drop.classList.add("dragging");
      });
    }
    for (const type of ["dragleave", "drop"]) {
      this.drop.addEventListener(type, () => this.drop.classList.remove("dragging"));
    }
    this.drop.addEventListener("drop", (e) => {
      e.preventDefault();
      const file = e.dataTransfer?.files?.[0];
      if (file) this.upload(file);
    });
    // Files dropped elsewhere must not make the browser leave the app.
    window.addEventListener("dragover", (e) => e.preventDefault());
    window.addEventListener("drop", (e) => e.preventDefault());
  }

  _status(text, kind) {
    this.status.textContent = text;
    this.status.dataset.kind = kind;
  }

  async upload(file) {
    this.progress.hidden = false;
    this.progress.value = 0;
    this._status(`Uploading ${file.name} (${formatBytes(file.size)})…`, "busy");
    try {
      const info = await uploadScene(file, (fraction) => {
        this.progress.value = fraction;
        if (fraction >= 1) this._status(`Checking ${file.name}…`, "busy");
      });
      const warnings = info.warnings.length ? ` Warnings: ${info.warnings.join("; ")}` : "";
      this._status(`Added ${info.name}: ${info.triangleCount.toLocaleString()} triangles, ${info.sphereCount} spheres.${warnings}`, "ok");
      await this.refresh();
      this.dispatchEvent(new CustomEvent("select", { detail: info.id }));
    } catch (e) {
      this._status(`${file.name} was not added: ${e.message}`, "error");
    } finally {
      this.progress.hidden = true;
    }
  }

  async refresh() {
    try {
      this.scenes = await listScenes();
    } catch (e) {
      this._status(`The scene list could not be loaded: ${e.message}`, "error");
      return this.scenes;
    }
    this._render();
    return this.scenes;
  }

  setSelected(id) {
    this.selected = id;
    this._render();
  }

  _render() {
    const items = this.scenes.map((scene) => {
      const li = document.createElement("li");
      li.className = "scene-item";
      const pick = document.createElement("button");
      pick.type = "button";
      pick.className = "scene-pick";
      pick.setAttribute("aria-pressed", String(scene.id === this.selected));
      pick.innerHTML = "<strong></strong><small></small>";
      pick.querySelector("strong").textContent = scene.name;
      const spheres = scene.sphereCount ? `, ${scene.sphereCount} spheres` : "";
      pick.querySelector("small").textContent = `${scene.triangleCount.toLocaleString()} triangles${spheres} · ${formatBytes(scene.sizeBytes)}`;
      pick.addEventListener("click", () => this.dispatchEvent(new CustomEvent("select", { detail: scene.id })));
      if (this.sharedReadOnly && !scene.owner) {
        // A sample on a server with named users: everyone's, no one deletes it.
        pick.querySelector("small").textContent += " · shared sample";
        li.append(pick);
        return li;
      }
      const remove = document.createElement("button");
      remove.type = "button";
      remove.className = "icon danger";
      remove.textContent = "✕";
      remove.title = `Delete ${scene.name}`;
      remove.setAttribute("aria-label", `Delete scene ${scene.name}`);
      remove.addEventListener("click", () => this._delete(scene));
      li.append(pick, remove);
      return li;
    });
    if (!items.length) items.push(Object.assign(document.createElement("li"), { className: "empty", textContent: "No scenes yet: upload one." }));
    this.list.replaceChildren(...items);
  }

  async _delete(scene) {
    if (!window.confirm(`Delete the scene ${scene.name} and stop its running jobs?`)) return;
    try {
      await deleteScene(scene.id);
      this._status(`Deleted ${scene.name}.`, "ok");
    } catch (e) {
      this._status(`${scene.name} could not be deleted: ${e.message}`, "error");
    }
    await this.refresh();
    this.dispatchEvent(new CustomEvent("deleted", { detail: scene.id }));
  }
}
