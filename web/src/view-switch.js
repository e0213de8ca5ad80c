// The main area shows the 3D view, the render, or the render wiped over the
// 3D view; the key "v" goes between the first two. Each keeps its own
// toolbar; the 3D view keeps its camera while hidden.

export class ViewSwitch extends EventTarget {
  constructor(doc) {
    super();
    const $ = (id) => doc.getElementById(id);
    this.buttons = { "3d": $("show-3d"), image: $("show-image"), wipe: $("show-wipe") };
    this.panes = {
      "3d": [$("viewport"), $("debug-toolbar")],
      image: [$("image-view"), $("image-tools")],
      wipe: [$("viewport"), $("image-view"), $("image-tools")],
    };
    this.imageView = $("image-view");
    this.current = "3d";
    for (const [name, button] of Object.entries(this.buttons)) button.addEventListener("click", () => this.show(name));
    doc.addEventListener("keydown", (e) => {
      const typing = e.target.closest?.("input, select, textarea");
      if (e.key === "v" && !typing && !e.ctrlKey && !e.metaKey && !e.altKey) this.show(this.current === "image" ? "3d" : "image");
    });
  }

  show(name) {
    this.current = name;
    const shown = new Set(this.panes[name]);
    for (const element of Object.values(this.panes).flat()) element.hidden = !shown.has(element);
    for (const [pane, button] of Object.entries(this.buttons)) button.setAttribute("aria-pressed", String(pane === name));
    this.imageView.classList.toggle("wipe", name === "wipe");
    this.dispatchEvent(new CustomEvent("change", { detail: name }));
  }
}
