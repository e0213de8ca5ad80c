// Which tree of a two-level BVH the boxes show: the top level over the
// instances, the tree of the triangles placed once, or one instance's own
// tree (by number, or by a button for each tree the traced ray entered).
// Hidden for a scene with one tree.
import { enteredTrees } from "./bvh-boxes.js";

const $ = (id) => document.getElementById(id);
const MAX_ENTERED_BUTTONS = 12;

export class BvhTreePicker {
  /** `guard` reports a failed box request (a promise) to the user. */
  constructor(bvh, guard) {
    this.bvh = bvh;
    this.guard = guard;
    this.pick = $("bvh-tree-pick");
    this.select = $("bvh-tree");
    this.instance = $("bvh-instance");
    this.name = $("bvh-instance-name");
    this.entered = $("bvh-entered");
    this.select.addEventListener("change", () => this._choose());
    this.instance.addEventListener("change", () => this._choose());
  }

  /** A BvhBoxes change: the scene's instance count decides what can be picked. */
  update({ tree, instanceCount, hasWorldTree, instanceName }) {
    this.pick.hidden = !instanceCount;
    this.select.querySelector('option[value="world"]').hidden = !hasWorldTree;
    this.instance.max = String(Math.max(instanceCount - 1, 0));
    const isInstance = tree !== "top" && tree !== "world";
    this.select.value = isInstance ? "instance" : tree;
    this.instance.hidden = !isInstance;
    if (isInstance) this.instance.value = tree;
    // Which node of the file placed it: the instance numbers are the loader's.
    this.name.textContent = isInstance && instanceName ? `node ${instanceName}` : "";
  }

  /** The trees below the top level that the traced ray's segments entered, as buttons that show them. */
  showEntered(segments) {
    const trees = segments ? enteredTrees(segments) : [];
    this.entered.hidden = trees.length === 0;
    if (!trees.length) {
      this.entered.replaceChildren();
      return;
    }
    const buttons = trees.slice(0, MAX_ENTERED_BUTTONS).map((tree) => {
      const button = document.createElement("button");
      button.type = "button";
      button.dataset.tree = tree;
      button.textContent = tree === "world" ? "placed once" : `instance ${tree}`;
      button.addEventListener("click", () => this._show(tree));
      return button;
    });
    const more = trees.length > MAX_ENTERED_BUTTONS ? [` and ${trees.length - MAX_ENTERED_BUTTONS} more`] : [];
    this.entered.replaceChildren("Trees the ray entered: ", ...buttons, ...more);
  }

  _choose() {
    const kind = this.select.value;
    if (kind !== "instance") {
      this._show(kind);
      return;
    }
    const count = this.bvh.instanceCount;
    const n = Math.min(Math.max(Math.trunc(Number(this.instance.value)) || 0, 0), Math.max(count - 1, 0));
    this.instance.value = String(n);
    this._show(String(n));
  }

  _show(tree) {
    this.guard(this.bvh.setTree(tree));
    if (!this.bvh.lines.visible) $("bvh-show").click();
  }
}
