// The main area shows the 3D view or the render; the tab key "v" switches.
// Each keeps its own toolbar; the 3D view keeps its camera while hidden.

export class ViewSwitch extends EventTarget {
  constructor(doc) {
    super();
    this.buttons = { "3d": doc.getElementById("show-3d"), image: doc.getElementById("show-image") };
    this.panes = {
      "3d": [doc.getElementById("viewport"), doc.getElementById("debug-toolbar")],
      image: [doc.getElementById("image-view"), doc.getElementById("image-tools")],
    };
    this.current = "3d";
    for (const [name, button] of Object.entries(this.buttons)) button.addEventListener("click", () => this.show(name));
    doc.addEventListener("keydown", (e) => {
      const typing = e.target.closest?.("input, select, textarea");
      if (e.key === "v" && !typing && !e.ctrlKey && !e.metaKey && !e.altKey) this.show(this.current === "3d" ? "image" : "3d");
    });
  }

  show(name) {
    this.current = name;
    for (const [pane, elements] of Object.entries(this.panes)) {
      for (const element of elements) element.hidden = pane !== name;
      this.buttons[pane].setAttribute("aria-pressed", String(pane === name));
    }
    this.dispatchEvent(new CustomEvent("change", { detail: name }));
  }
}
